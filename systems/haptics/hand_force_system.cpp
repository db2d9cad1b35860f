#include "systems/haptics/hand_force_system.hpp"

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

namespace {
void send(ecs::Registry& r, const HandCube& cube, const HandForce& force) {
    auto* devices = r.resource<HandDevices>();
    if (auto* device = devices ? devices->device(cube.hand) : nullptr) {
        // A failed write is counted here for the HUD and the figures; the safety chain counts it too and,
        // after a few in a row, zeroes, drops and reopens the device (SafeForceDevice).
        if (!device->send_force(force.force_n)) {
            if (auto* links = r.resource<HandLinks>()) ++links->write_failures[cube.hand];
        }
        if (auto* watchdog = devices->watchdog(cube.hand)) watchdog->feed();
    }
    if (auto* log = r.resource<SentForceLog>(); log && log->enabled && cube.hand < 2) log->hand[cube.hand].push_back(force.force_n);
}
} // namespace

glm::dvec3 hand_feels(ecs::Registry& r, const HandCube& cube, const HandInput& input, const HandProxy& proxy, const HandGrip& grip) {
    const auto* coupling = r.resource<const HandCoupling>();
    if (!coupling || !input.connected || cube.hand >= 2) return glm::dvec3{0.0};
    // Virtual coupling: a spring and a damper between the device and the proxy it drives.
    glm::dvec3 force = coupling->n_per_m[cube.hand] * (proxy.position_m - input.device_m) +
                       coupling->damping_ns_per_m[cube.hand] * proxy.slip_m_s;
    if (!grip.held.is_null()) {
        // The stem's pull on the points the grip holds: its weight, its bending, its stretch between two
        // hands, as the physics computed it this tick.
        if (const auto* loads = r.try_get<const StemLoads>(grip.held); loads && grip.held_point < loads->force_n.size()) {
            force += loads->force_n[grip.held_point];
            if (grip.holds_direction && grip.second_point < loads->force_n.size()) force += loads->force_n[grip.second_point];
        }
        // Bending: the thumbs push the middle with F^b (Eq. 5); each hand takes half of it back.
        if (const auto* bend = r.try_get<const Bending>(grip.held); bend && bend->active) force -= 0.5 * bend->force_n * bend->push_direction;
    }
    return force;
}

void HandForceSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<const HandCube, const HandInput, const HandProxy, const HandGrip, HandForce>().each(
        [&](ecs::Entity, const HandCube& cube, const HandInput& input, const HandProxy& proxy, const HandGrip& grip, HandForce& force) {
            force.force_n = hand_feels(r, cube, input, proxy, grip);
            send(r, cube, force);
        });
}

void ForceCheckSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<const HandCube, const HandInput, const HandProxy, const HandGrip, ForceChecks>().each(
        [&](ecs::Entity, const HandCube& cube, const HandInput& input, const HandProxy& proxy, const HandGrip& grip, ForceChecks& checks) {
            checks.previous_n = checks.last_n;
            checks.previous_us = checks.last_us;
            checks.last_n = hand_feels(r, cube, input, proxy, grip);
            checks.last_us = ctx.time_us;
            ++checks.checks;
        });
}

void ForceEstimateSystem::operator()(sched::SystemContext& ctx) {
    ctx.registry.view<const HandInput, const ForceChecks, HandForce>().each(
        [&](ecs::Entity, const HandInput& input, const ForceChecks& checks, HandForce& force) {
            if (!input.connected) {
                force.force_n = glm::dvec3{0.0};
                return;
            }
            glm::dvec3 estimate = checks.last_n;
            if (checks.checks >= 2 && checks.last_us > checks.previous_us) {
                const glm::dvec3 moving = (checks.last_n - checks.previous_n) / static_cast<double>(checks.last_us - checks.previous_us);
                estimate += moving * static_cast<double>(ctx.time_us - checks.last_us);
            }
            force.force_n = estimate;
        });
}

void ForceOutputSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    r.view<const HandCube, const HandInput, HandForce>().each([&](ecs::Entity, const HandCube& cube, const HandInput& input, HandForce& force) {
        if (!input.connected) force.force_n = glm::dvec3{0.0};
        send(r, cube, force);
    });
}

} // namespace ikebana::systems
