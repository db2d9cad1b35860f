#pragma once
// The insertion module: cuts and the scripted insertion hand (input), then which pins a stem end meets,
// their resistance and the kenzan's grip (insertion phase). Installed before the haptics module, so a
// cut or a scripted hand acts on a stem before a device hand grabs it in the same tick.
#include "engine/core/result.hpp"
#include "engine/sched/fwd.hpp"

namespace ikebana::systems {
Result<void> install_insertion(sched::Schedule& schedule);
} // namespace ikebana::systems
