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
    frame.stems.clear();
    std::uint32_t index = 0;
    ctx.registry.view<components::Flower, components::StemPoints>().each(
        [&](ecs::Entity, components::Flower&, components::StemPoints& points) {
            frame.stems.push_back({index++, points.position_m});
        });
    for (auto& h : frame.hands) h = components::HandStatus{false, false, 0};
    ctx.registry.view<components::HandState>().each([&](ecs::Entity, components::HandState& hand) {
        if (hand.hand < 2) frame.hands[hand.hand] = components::HandStatus{true, hand.connected, hand.disconnects};
    });
    const auto* contacts = ctx.registry.resource<components::Contacts>();
    frame.contacts = contacts ? contacts->list.size() : 0;
    const auto* list = ctx.registry.resource<render::DrawList>();
    frame.draw_list = list ? *list : render::DrawList{};
    (*channel)->buffer.publish();
}

} // namespace ikebana::systems
