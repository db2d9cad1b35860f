#include "systems/haptics/hand_force_system.hpp"

#include "engine/ecs/registry.hpp"
#include "systems/haptics/hand_devices.hpp"

namespace ikebana::systems {

using namespace components;

void HandForceSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    const auto* devices = r.resource<HandDevices>();
    if (!devices) return;
    const auto* settings = r.resource<PhysicsSettings>();
    const glm::dvec3 g = settings ? settings->gravity_m_s2 : PhysicsSettings{}.gravity_m_s2;
    r.view<HandState>().each([&](ecs::Entity, HandState& hand) {
        if (!hand.connected) {
            hand.force_n = glm::dvec3{0.0};
            return;
        }
        // Virtual coupling: a spring and a damper between the device and the proxy it drives.
        glm::dvec3 force = devices->coupling_n_per_m * (hand.proxy_m - hand.device_m) + devices->coupling_damping_n_s_per_m * hand.slip_m_s;
        if (!hand.held.is_null()) {
            auto* points = r.try_get<StemPoints>(hand.held);
            auto* rest = r.try_get<StemRestShape>(hand.held);
            auto* springs = r.try_get<StemSprings>(hand.held);
            if (points && rest && springs && hand.held_point < points->position_m.size()) {
                physics::stem_forces(*points, *rest, *springs, r.try_get<StemClamp>(hand.held), g, force_scratch);
                force += force_scratch[hand.held_point];
            }
        }
        hand.force_n = force;
        if (hand.hand < 2 && devices->device[hand.hand]) (void)devices->device[hand.hand]->send_force(force);
    });
}

} // namespace ikebana::systems
