#include "systems/haptics/workspace_view_system.hpp"

#include <cstdio>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void WorkspaceViewSystem::operator()(sched::SystemContext& ctx) {
    auto* port = ctx.registry.resource<ecs::Port<ViewChannel>>();
    if (!port) return;
    ViewChannel& view = port->use();
    const double yaw = view.yaw_rad.load(std::memory_order_relaxed);
    if (view.log && yaw != view.logged_yaw_rad) {
        char line[64];
        const int n = std::snprintf(line, sizeof line, "%lld,view,0,%.17g\n", static_cast<long long>(ctx.time_us), yaw);
        (void)view.log->write(std::string_view(line, static_cast<std::size_t>(n)));
        view.logged_yaw_rad = yaw;
    }
    ctx.registry.view<components::WorkspaceMapping>().each([&](ecs::Entity, components::WorkspaceMapping& m) { m.yaw_rad = yaw; });
}

} // namespace ikebana::systems
