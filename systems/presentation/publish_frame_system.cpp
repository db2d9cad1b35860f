#include "systems/presentation/publish_frame_system.hpp"

#include "components/hand.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::systems {

void PublishFrameSystem::operator()(sched::SystemContext& ctx) {
    auto* const* channel = ctx.registry.resource<FrameChannel* const>();
    if (!channel || !*channel) return;
    auto& frame = (*channel)->buffer.write_buffer();
    frame.sim_time_us = ctx.time_us;
    frame.flowers.clear();
    auto& r = ctx.registry;
    r.view<const components::Flower, const components::StemPoints>().each([&](ecs::Entity e, const components::Flower& flower, const components::StemPoints& points) {
        components::FlowerStatus status{flower.species, points.position_m, 0, false, false, false, 0.0, 0.0};
        if (const auto* h = r.try_get<const components::InsertionHistory>(e)) {
            status.insertions = h->insertions_total;
            status.bottom_broken = h->bottom_broken;
        }
        if (const auto* engagement = r.try_get<const components::PinEngagement>(e)) {
            status.in_kenzan = engagement->in_kenzan;
            status.holding_moment_nm = engagement->holding_moment_nm;
            status.gravity_moment_nm = engagement->gravity_moment_nm;
        }
        if (const auto* grip = r.try_get<const components::KenzanGrip>(e)) status.fallen = grip->fallen;
        frame.flowers.push_back(std::move(status));
    });
    for (auto& h : frame.hands) h = components::HandStatus{false, false, 0, false, glm::dvec3{0.0}};
    r.view<const components::HandCube, const components::HandInput, const components::HandGrip, const components::HandForce>().each(
        [&](ecs::Entity, const components::HandCube& cube, const components::HandInput& input, const components::HandGrip& grip,
            const components::HandForce& force) {
            if (cube.hand < 2) frame.hands[cube.hand] = components::HandStatus{true, input.connected, input.disconnects, !grip.held.is_null(), force.force_n};
        });
    const auto* contacts = ctx.registry.resource<const components::Contacts>();
    frame.contacts = contacts ? contacts->list.size() : 0;
    const auto* list = ctx.registry.resource<const render::DrawList>();
    frame.draw_list = list ? *list : render::DrawList{};
    (*channel)->buffer.publish();
}

} // namespace ikebana::systems
