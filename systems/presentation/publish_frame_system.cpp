#include "systems/presentation/publish_frame_system.hpp"

#include "components/hand.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::systems {

void PublishFrameSystem::operator()(sched::SystemContext& ctx) {
    auto** channel = ctx.registry.resource<FrameChannel*>();
    if (!channel || !*channel) return;
    auto& frame = (*channel)->buffer.write_buffer();
    frame.sim_time_us = ctx.time_us;
    frame.flowers.clear();
    auto& r = ctx.registry;
    r.view<components::Flower, components::StemPoints>().each([&](ecs::Entity e, components::Flower& flower, components::StemPoints& points) {
        components::FlowerStatus status{flower.species, points.position_m, 0, false, false, false, 0.0, 0.0};
        if (const auto* h = r.try_get<components::InsertionHistory>(e)) {
            status.insertions = h->insertions_total;
            status.bottom_broken = h->bottom_broken;
        }
        if (const auto* engagement = r.try_get<components::PinEngagement>(e)) {
            status.in_kenzan = engagement->in_kenzan;
            status.holding_moment_nm = engagement->holding_moment_nm;
            status.gravity_moment_nm = engagement->gravity_moment_nm;
        }
        if (const auto* grip = r.try_get<components::KenzanGrip>(e)) status.fallen = grip->fallen;
        frame.flowers.push_back(std::move(status));
    });
    for (auto& h : frame.hands) h = components::HandStatus{false, false, 0, false, glm::dvec3{0.0}};
    r.view<components::HandState>().each([&](ecs::Entity, components::HandState& hand) {
        if (hand.hand < 2) frame.hands[hand.hand] = components::HandStatus{true, hand.connected, hand.disconnects, !hand.held.is_null(), hand.force_n};
    });
    const auto* contacts = ctx.registry.resource<components::Contacts>();
    frame.contacts = contacts ? contacts->list.size() : 0;
    const auto* list = ctx.registry.resource<render::DrawList>();
    frame.draw_list = list ? *list : render::DrawList{};
    (*channel)->buffer.publish();
}

} // namespace ikebana::systems
