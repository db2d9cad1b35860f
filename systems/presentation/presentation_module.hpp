#pragma once
// The presentation module: what the main lane needs to show the world crosses from the simulation lane.
#include "engine/core/result.hpp"
#include "engine/sched/fwd.hpp"

namespace ikebana::systems {
Result<void> install_presentation(sched::Schedule& schedule);
} // namespace ikebana::systems
