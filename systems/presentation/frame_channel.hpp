#pragma once
// The channel from the simulation lane to the main lane. The World owns it; each lane's registry holds
// a FrameChannel* resource pointing at it.
#include <functional>
#include <string>

#include "components/snapshot.hpp"
#include "engine/sched/triple_buffer.hpp"

namespace ikebana::systems {

struct FrameChannel {
    sched::TripleBuffer<components::FrameSnapshot> buffer;
};

// What the main lane has received (main-lane resource).
struct ReceivedFrames {
    std::uint64_t frames = 0;
    std::uint64_t fresh = 0; // frames that brought a new snapshot
    components::FrameSnapshot latest;
    // Called on the main lane when something the trainee should hear about happens (a device
    // unplugged or back); the app decides how to say it (a line on the terminal, the HUD).
    std::function<void(const std::string&)> announce;
};

} // namespace ikebana::systems
