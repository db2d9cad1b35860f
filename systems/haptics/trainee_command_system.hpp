#pragma once
// What the trainee asks of a held stem beyond moving it, from the window (a key) or a scripted
// trainee (the lesson demo): cut it to a length, or prune at the hand (a twig off, a leaf stripped:
// pruning_system). The main thread pushes commands into the channel;
// this system, on the simulation's thread, turns each into a CutRequest on the stem that hand holds
// (the cutting system does the cut: section 1's cutting, the same for every caller).
#include <cstdint>
#include <string_view>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/core/async_line_writer.hpp"
#include "engine/core/spsc_ring.hpp"
#include "engine/ecs/port.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct TraineeCommand {
    enum class Kind : std::uint8_t { cut, prune };
    Kind kind = Kind::cut;
    std::uint8_t hand = 0;
    double keep_length_m = 0.0; // cut: the stem's length after the cut (what is cut off is its bottom); prune: 0
};

// Main thread (or a driver) to simulation thread; the World owns it (each lane's registry holds an ecs::Port).
// One producer (the main thread, or the driver of a headless demonstration) and one consumer (the
// simulation): a lock-free ring, so the 1 kHz thread never waits for the main thread.
class TraineeChannel {
public:
    // False when 64 commands are already waiting (a trainee cannot press that fast): the command is
    // not taken, and the caller says so.
    [[nodiscard]] bool push(const TraineeCommand& command) noexcept { return pending_.push(command); }
    [[nodiscard]] bool pop(TraineeCommand& command) noexcept { return pending_.pop(command); }
    // When set (before the session runs): each command as the simulation takes it, one CSV line
    // "time_us,cut,hand,keep_length_m" or "time_us,prune,hand,0", so that a replay gives it at the same tick.
    AsyncLineWriter* log = nullptr;

private:
    SpscRing<TraineeCommand> pending_{64};
};

struct TraineeCommandSystem {
    static constexpr std::string_view name = "trainee_commands";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::HandCube, components::HandGrip, components::StemRestShape>;
    // The Port: taking a command off the channel is a write.
    using writes = sched::Components<ecs::Port<TraineeChannel>, components::CutRequest, components::PruneRequest>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
