#pragma once
// The collision module: colliders follow their parts, then the broad and narrow phase find contacts.
#include "engine/core/result.hpp"
#include "engine/sched/fwd.hpp"

namespace ikebana::systems {
Result<void> install_collision(sched::Schedule& schedule);
} // namespace ikebana::systems
