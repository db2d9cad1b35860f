#pragma once
// The presentation module, extract -> prepare -> draw (Bevy's render world): the simulation lane publishes
// plain state (publish_frame, its last phase); the main lane receives it (receive), and prepares the
// draw list and the HUD (prepare); whoever shows the frame draws PreparedFrame in the main lane's
// "draw" phase (the window, `ikebana render`).
#include "engine/core/result.hpp"
#include "engine/sched/fwd.hpp"

namespace ikebana::systems {
Result<void> install_presentation(sched::Schedule& schedule);
} // namespace ikebana::systems
