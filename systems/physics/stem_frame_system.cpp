#include "systems/physics/stem_frame_system.hpp"

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void StemFrameSystem::operator()(sched::SystemContext& ctx) {
    if (const auto* capacity = ctx.registry.resource<const components::BodyCapacity>(); capacity && capacity != sized_for_) {
        physics::reserve_scratch(scratch_, capacity->points);
        sized_for_ = capacity;
    }
    ctx.registry.view<components::StemFrame, const components::StemPoints, const components::StemRestShape, const components::StemSprings>().each(
        [&](ecs::Entity, components::StemFrame& frame, const components::StemPoints& points, const components::StemRestShape& rest,
            const components::StemSprings& springs) { physics::update_frame(frame, points.position_m, rest, springs.hinge_nm_per_rad, scratch_); });
}

} // namespace ikebana::systems
