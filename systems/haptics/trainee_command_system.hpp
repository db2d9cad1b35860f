#pragma once
// What the trainee asks of a held stem beyond moving it, from the window (a key) or a scripted
// trainee (the lesson demo): cut it to a length. The main thread pushes commands into the channel;
// this system, on the simulation's thread, turns each into a CutRequest on the stem that hand holds
// (the cutting system does the cut: section 1's cutting, the same for every caller).
#include <cstdint>
#include <mutex>
#include <ostream>
#include <utility>
#include <string_view>
#include <vector>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct TraineeCommand {
    enum class Kind : std::uint8_t { cut };
    Kind kind = Kind::cut;
    std::uint8_t hand = 0;
    double keep_length_m = 0.0; // cut: the stem's length after the cut (what is cut off is its bottom)
};

// Main thread (or a driver) to simulation thread; the World owns it (the sim registry holds a pointer).
class TraineeChannel {
public:
    void push(const TraineeCommand& command) {
        const std::lock_guard lock(mutex_);
        pending_.push_back(command);
    }
    std::vector<TraineeCommand> take() {
        const std::lock_guard lock(mutex_);
        return std::exchange(pending_, {});
    }
    // When set (before the session runs): each command as the simulation takes it, one CSV line
    // "time_us,cut,hand,keep_length_m", so that a replay gives it at the same tick.
    std::ostream* log = nullptr;

private:
    std::mutex mutex_;
    std::vector<TraineeCommand> pending_;
};

struct TraineeCommandSystem {
    static constexpr std::string_view name = "trainee_commands";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<TraineeChannel*, components::HandCube, components::HandGrip, components::StemRestShape>;
    using writes = sched::Components<components::CutRequest>;

    void operator()(sched::SystemContext& ctx);
};

} // namespace ikebana::systems
