#include "systems/haptics/workspace_view_system.hpp"

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void WorkspaceViewSystem::operator()(sched::SystemContext& ctx) {
    auto* const* channel = ctx.registry.resource<ViewChannel* const>();
    if (!channel || !*channel) return;
    const double yaw = (*channel)->yaw_rad.load(std::memory_order_relaxed);
    ctx.registry.view<components::WorkspaceMapping>().each([&](ecs::Entity, components::WorkspaceMapping& m) { m.yaw_rad = yaw; });
}

} // namespace ikebana::systems
