#include "systems/haptics/hand_input_system.hpp"

#include <cmath>

#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/haptics/hand_devices.hpp"

namespace ikebana::systems {

using namespace components;

bool held_by_another_hand(ecs::Registry& r, const HandState& hand, std::uint32_t point) {
    bool other = false;
    r.view<HandState>().each([&](ecs::Entity, HandState& h) {
        if (&h == &hand || h.held != hand.held) return;
        other = other || h.held_point == point || (h.holds_direction && h.second_point == point);
    });
    return other;
}

void let_go_of_direction(ecs::Registry& r, HandState& hand) {
    if (!hand.holds_direction) return;
    hand.holds_direction = false;
    auto* points = r.try_get<StemPoints>(hand.held);
    if (points && hand.second_point < points->pinned.size() && hand.second_point != hand.held_point &&
        !held_by_another_hand(r, hand, hand.second_point))
        points->pinned[hand.second_point] = 0;
}

void release_hold(ecs::Registry& r, HandState& hand) {
    if (hand.held.is_null()) return;
    let_go_of_direction(r, hand);
    if (auto* points = r.try_get<StemPoints>(hand.held); points && hand.held_point < points->pinned.size()) {
        if (!held_by_another_hand(r, hand, hand.held_point)) points->pinned[hand.held_point] = 0;
    }
    if (auto* grasp = r.try_get<Grasp>(hand.held); grasp && grasp->hands > 0) --grasp->hands;
    hand.held = ecs::null_entity;
}

void HandInputSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    const auto* devices = r.resource<HandDevices>();
    if (!devices) return;
    const auto* table = r.resource<Table>();
    const Kenzan* kenzan = r.single<Kenzan>();
    r.view<HandState, WorkspaceMapping, HandCube, Collider>().each(
        [&](ecs::Entity, HandState& hand, WorkspaceMapping& map, HandCube& cube, Collider& collider) {
            devices::HapticDevice* device = hand.hand < 2 ? devices->device[hand.hand] : nullptr;
            if (!device) return;
            const auto sample = device->poll(ctx.time_us);
            if (!sample) {
                if (hand.connected) {
                    release_hold(r, hand);
                    hand.force_n = glm::dvec3{0.0};
                    (void)device->send_force(glm::dvec3{0.0});
                    ++hand.disconnects;
                }
                hand.connected = false;
                return;
            }
            hand.connected = true;
            if (devices->recorder[hand.hand]) devices->recorder[hand.hand]->record(*sample);
            const double c = std::cos(map.yaw_rad);
            const double s = std::sin(map.yaw_rad);
            auto turn = [&](glm::dvec3 v) { return glm::dvec3{c * v.x - s * v.y, s * v.x + c * v.y, v.z}; };
            const glm::dvec3 previous_device = hand.device_m;
            if (device->capabilities().reports_position) {
                hand.device_m = map.centre_m + turn(map.scale * sample->position);
            } else {
                hand.device_m += turn(sample->position * map.rate_speed_m_s * ctx.dt_s);
            }
            hand.rotation_rad = sample->rotation;
            hand.previous_buttons = hand.buttons;
            hand.buttons = sample->buttons;
            // The proxy: the device position, kept above the table and out of the kenzan's base.
            glm::dvec3 proxy = hand.device_m;
            const double half = 0.5 * cube.edge_m;
            if (table) proxy.z = std::max(proxy.z, table->height_m + half);
            if (kenzan) {
                const glm::dvec3 lo = kenzan->pin_base(0, 0) - glm::dvec3{kenzan->pitch_m};
                const glm::dvec3 hi = kenzan->pin_base(kenzan->columns - 1, kenzan->rows - 1) + glm::dvec3{kenzan->pitch_m};
                if (proxy.x > lo.x - half && proxy.x < hi.x + half && proxy.y > lo.y - half && proxy.y < hi.y + half) {
                    proxy.z = std::max(proxy.z, kenzan->origin_m.z + half);
                }
            }
            const glm::dvec3 slip = proxy - hand.device_m;
            hand.slip_m_s = ctx.dt_s > 0.0 ? (slip - (hand.proxy_m - previous_device)) / ctx.dt_s : glm::dvec3{0.0};
            hand.proxy_m = proxy;
            collider.a_m = proxy;
            collider.b_m = proxy;
        });
}

} // namespace ikebana::systems
