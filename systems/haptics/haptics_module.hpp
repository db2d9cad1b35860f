#pragma once
// The haptics module, the hand chain in the order a tick runs it: the workspace follows the view, each
// device is read into its hand (hand_input), the hand grabs and lets go (grab), two hands bend (bending);
// after the physics, what each hand feels goes back to its device, by one of two force schemes
// (hand_force_system.hpp).
#include <string>

#include "engine/core/result.hpp"
#include "engine/sched/fwd.hpp"

namespace ikebana::systems {

enum class ForceScheme { full_rate, paper };

Result<void> install_haptics(sched::Schedule& schedule, ForceScheme scheme);

} // namespace ikebana::systems
