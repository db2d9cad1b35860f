#pragma once
// The hands' workspace follows the camera: the main thread, which turns the view, writes the yaw into
// the ViewChannel; this system, on the simulation's thread, copies it into every WorkspaceMapping, so
// that pushing a device "forward" still moves the hand away from the viewer. Nothing else crosses
// from the main thread into the simulation's registry.
#include <atomic>
#include <string_view>

#include "components/hand.hpp"
#include "engine/core/async_line_writer.hpp"
#include "engine/ecs/port.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

// Main thread to simulation thread (the World owns it; each lane's registry holds an ecs::Port to it).
struct ViewChannel {
    std::atomic<double> yaw_rad{0.0};
    // When set (before the session runs): each new yaw as the simulation takes it, one CSV line
    // "time_us,view,0,yaw_rad" (a session's commands.csv), so that a replay turns at the same tick.
    AsyncLineWriter* log = nullptr;
    double logged_yaw_rad = 0.0; // the simulation thread's: the last yaw it wrote down
};

struct WorkspaceViewSystem {
    static constexpr std::string_view name = "workspace_view";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<>;
    // The Port: taking the yaw and writing it down in the log change the channel.
    using writes = sched::Components<ecs::Port<ViewChannel>, components::WorkspaceMapping>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
