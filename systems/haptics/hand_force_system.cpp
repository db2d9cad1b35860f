#include "systems/haptics/hand_force_system.hpp"

#include "engine/ecs/registry.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "systems/physics/stem_dynamics.hpp"

namespace ikebana::systems {

using namespace components;

namespace {
void send(ecs::Registry& r, const HandState& hand) {
    const auto* devices = r.resource<HandDevices>();
    if (devices && hand.hand < 2 && devices->device[hand.hand]) {
        (void)devices->device[hand.hand]->send_force(hand.force_n);
        if (devices->watchdog[hand.hand]) devices->watchdog[hand.hand]->feed();
    }
    if (auto* log = r.resource<SentForceLog>(); log && log->enabled && hand.hand < 2) log->hand[hand.hand].push_back(hand.force_n);
}
} // namespace

glm::dvec3 hand_feels(ecs::Registry& r, const HandState& hand, std::vector<glm::dvec3>& scratch) {
    const auto* devices = r.resource<HandDevices>();
    if (!devices || !hand.connected) return glm::dvec3{0.0};
    // Virtual coupling: a spring and a damper between the device and the proxy it drives.
    glm::dvec3 force = devices->coupling_n_per_m * (hand.proxy_m - hand.device_m) + devices->coupling_damping_n_s_per_m * hand.slip_m_s;
    if (!hand.held.is_null()) {
        const auto* settings = r.resource<PhysicsSettings>();
        const glm::dvec3 g = settings ? settings->gravity_m_s2 : PhysicsSettings{}.gravity_m_s2;
        auto* points = r.try_get<StemPoints>(hand.held);
        auto* rest = r.try_get<StemRestShape>(hand.held);
        auto* springs = r.try_get<StemSprings>(hand.held);
        if (points && rest && springs && hand.held_point < points->position_m.size()) {
            physics::stem_forces(*points, *rest, *springs, r.try_get<StemClamp>(hand.held), g, scratch);
            force += scratch[hand.held_point];
            if (hand.holds_direction && hand.second_point < scratch.size()) force += scratch[hand.second_point];
        }
        // Bending: the thumbs push the middle with F^b (Eq. 5); each hand takes half of it back.
        if (const auto* bend = r.try_get<Bending>(hand.held); bend && bend->active) force -= 0.5 * bend->force_n * bend->push_direction;
    }
    return force;
}

void HandForceSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<HandState>().each([&](ecs::Entity, HandState& hand) {
        hand.force_n = hand_feels(r, hand, scratch);
        send(r, hand);
    });
}

void ForceCheckSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<HandState, ForceChecks>().each([&](ecs::Entity, HandState& hand, ForceChecks& checks) {
        checks.previous_n = checks.last_n;
        checks.previous_us = checks.last_us;
        checks.last_n = hand_feels(r, hand, scratch);
        checks.last_us = ctx.time_us;
        ++checks.checks;
    });
}

void ForceEstimateSystem::operator()(sched::SystemContext& ctx) {
    ctx.registry.view<HandState, ForceChecks>().each([&](ecs::Entity, HandState& hand, ForceChecks& checks) {
        if (!hand.connected) {
            hand.force_n = glm::dvec3{0.0};
            return;
        }
        glm::dvec3 estimate = checks.last_n;
        if (checks.checks >= 2 && checks.last_us > checks.previous_us) {
            const glm::dvec3 moving = (checks.last_n - checks.previous_n) / static_cast<double>(checks.last_us - checks.previous_us);
            estimate += moving * static_cast<double>(ctx.time_us - checks.last_us);
        }
        hand.force_n = estimate;
    });
}

void ForceOutputSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<HandState>().each([&](ecs::Entity, HandState& hand) {
        if (!hand.connected) hand.force_n = glm::dvec3{0.0};
        send(r, hand);
    });
}

} // namespace ikebana::systems
