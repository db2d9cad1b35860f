#include "scripted_hands.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "components/hand.hpp"
#include "game/world/world.hpp"

namespace ikebana::test {

game::SceneDef kenzan_bench() {
    game::SceneDef scene{};
    scene.seed = 1;
    scene.gravity_m_s2 = {0, 0, -9.80665};
    scene.kenzan_layout = "standard";
    scene.kenzan_position_m = {0, 0, 0.008};
    return scene;
}

void add_two_hands(game::SceneDef& scene, glm::dvec3 left_m, glm::dvec3 right_m) {
    scene.hands.push_back({0, left_m, 0.02, ""});
    scene.hands.push_back({1, right_m, 0.02, ""});
}

std::unique_ptr<game::World> world_of(const game::SceneDef& scene) {
    auto world = game::World::create(scene);
    EXPECT_TRUE(world) << (world ? "" : world.error().message);
    return world ? std::move(world).value() : nullptr;
}

std::unique_ptr<devices::ScriptedDevice> script(const std::vector<Key>& keys) {
    std::ostringstream csv;
    csv << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n";
    for (const auto& k : keys) csv << k.t << "," << k.x << "," << k.y << "," << k.z << ",0,0,0," << k.buttons << "\n";
    auto parsed = devices::parse_trajectory(csv.str(), "test");
    EXPECT_TRUE(parsed) << (parsed ? "" : parsed.error().message);
    return std::make_unique<devices::ScriptedDevice>(std::move(parsed).value(), devices::ScriptedDevice::Mode::interpolate);
}

HandView hand_view(game::World& w, std::size_t hand) {
    const auto e = w.hands[hand];
    const auto& input = w.sim.get<components::HandInput>(e);
    const auto& proxy = w.sim.get<components::HandProxy>(e);
    const auto& grip = w.sim.get<components::HandGrip>(e);
    const auto& force = w.sim.get<components::HandForce>(e);
    return HandView{input.connected, input.disconnects, input.device_m, proxy.position_m, grip.held, grip.held_point, grip.held_offset_m,
                    grip.holds_direction, grip.second_point, force.force_n};
}

} // namespace ikebana::test
