#pragma once
// Scripted hands for the end-to-end haptics tests: a device that follows keyframes.
#include <memory>
#include <vector>

#include "engine/devices/scripted_device.hpp"
#include "engine/ecs/entity.hpp"

#include "game/scene/scene.hpp"

namespace ikebana::game {
class World;
}

namespace ikebana::test {

// The bench the haptics tests share: seed 1, gravity, the standard kenzan on the table at the origin;
// no flowers and no hands (each test puts its own).
game::SceneDef kenzan_bench();
// The hands most tests use: left and right at these places, 2 cm cubes.
void add_two_hands(game::SceneDef& scene, glm::dvec3 left_m, glm::dvec3 right_m);
// A world of the scene; one that does not build fails the test (and is null).
std::unique_ptr<game::World> world_of(const game::SceneDef& scene);

// One hand's four components read together, for assertions.
struct HandView {
    bool connected;
    std::uint64_t disconnects;
    glm::dvec3 device_m;
    glm::dvec3 proxy_m;
    ecs::Entity held;
    std::uint32_t held_point;
    glm::dvec3 held_offset_m;
    bool holds_direction;
    std::uint32_t second_point;
    glm::dvec3 force_n;
};
HandView hand_view(game::World& world, std::size_t hand);

// A keyframe as (t, x, y, z, buttons); seconds and metres in the world frame.
struct Key {
    double t, x, y, z;
    int buttons;
};

// A device that moves between the keys in straight lines.
std::unique_ptr<devices::ScriptedDevice> script(const std::vector<Key>& keys);

} // namespace ikebana::test
