#pragma once
// The physics module: the spring stems integrated at the haptic rate, then held above the table.
#include "engine/core/result.hpp"
#include "engine/sched/fwd.hpp"

namespace ikebana::systems {
Result<void> install_physics(sched::Schedule& schedule);
} // namespace ikebana::systems
