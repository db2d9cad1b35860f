#pragma once
// While the haptic loop runs on its own thread, every hand whose device pushes gets a watchdog: if the
// loop falls silent for 2 ms (a stall, a debugger, a crash of the loop), that device is sent zero
// force from the watchdog's own thread. Used by `sim --realtime` and the trainee app.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/devices/force_safety.hpp"
#include "engine/sched/clocks.hpp"

namespace ikebana::game {

class World;

class HandForceWatchdogs {
public:
    explicit HandForceWatchdogs(World& world);
    // Unhooks the watchdogs from the world's hands before they stop (after the loop has ended).
    ~HandForceWatchdogs();
    HandForceWatchdogs(const HandForceWatchdogs&) = delete;
    HandForceWatchdogs& operator=(const HandForceWatchdogs&) = delete;

    [[nodiscard]] bool armed(std::size_t hand) const { return hand < 2 && dogs_[hand] != nullptr; }
    [[nodiscard]] std::uint64_t trips(std::size_t hand) const { return armed(hand) ? dogs_[hand]->trips() : 0; }

private:
    World& world_;
    std::array<std::unique_ptr<devices::ForceWatchdog>, 2> dogs_;
};

// How a real-time run ended when not as asked (time up, Esc, the window closed): a lane that threw
// (the clock zeroed every pushing device at once), or SIGINT/SIGTERM (the caller zeroes them as it
// ends). `why` is the sentence to say, `exit_code` the status to end with (128 + the signal, or 1);
// both empty and 0 when it ended as asked.
struct RunEnding {
    std::string why;
    int exit_code = 0;
};
[[nodiscard]] RunEnding how_the_run_ended(const sched::Schedule& schedule, const std::vector<sched::LaneReport>& lanes);
// The same for SIGINT/SIGTERM alone (a loop outside the clock: the start screen).
[[nodiscard]] RunEnding stopped_by_signal();

} // namespace ikebana::game
