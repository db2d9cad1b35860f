#pragma once
// Two ways to drive one schedule.
//
// DeterministicClock: one thread, every lane, one integer-microsecond timeline, as fast as the CPU
// allows. Same schedule, same inputs: bit-identical world. Used by `sim`, `experiment`, tests.
//
// RealtimeClock: the same timeline paced by the monotonic clock. Lanes marked LaneThread::own (the
// 1 kHz haptic loop) run on their own thread with absolute deadlines, the others on the caller's
// thread. Lanes share no registry; data crosses threads only through TripleBuffer snapshots
// (engine/sched/triple_buffer.hpp). When a lane falls behind by more than its catch-up window, the
// firings it missed are dropped and counted instead of run back to back (no spiral of death).
#include <optional>
#include <atomic>
#include <string>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "engine/sched/schedule.hpp"

namespace ikebana::sched {

// The name of the lane whose system the calling thread is running now, on either clock; nullptr
// between systems and on threads that run none. For checks that hold per lane (tests count the
// allocations made while the 1 kHz lane runs).
[[nodiscard]] const char* running_lane() noexcept;
// And the system's name (engine/sched/schedule.cpp sets it while the system runs and while its queued
// changes are applied); nullptr between systems.
[[nodiscard]] const char* running_system() noexcept;

class DeterministicClock {
public:
    explicit DeterministicClock(Schedule& schedule);

    // Runs every firing due before t_us (half-open: one second at 1000 Hz is 1000 firings).
    void run_until(std::int64_t t_us);
    void run_for_us(std::int64_t duration_us) { run_until(now_us_ + duration_us); }
    [[nodiscard]] std::int64_t now_us() const noexcept { return now_us_; }
    // Where the timeline stands: the clock and each system's next firing (with the lanes' registries
    // saved beside it, a moment to come back to; a replay's snapshots).
    struct Moment {
        std::int64_t now_us = 0;
        std::vector<std::pair<std::uint64_t, std::int64_t>> firings; // per system in order: index, due time
    };
    [[nodiscard]] Moment moment() const;
    // Back (or on) to `m`, taken from this schedule or one built the same way; false (nothing changed)
    // when its systems are not as many as this schedule's.
    bool resume_from(const Moment& m);
    // Drops one lane's firings due before `until_us` without running them, as the real-time clock's
    // catch-up clamp did (a recording of a real-time session says when): the replay then skips too.
    void skip_lane(std::size_t lane, std::int64_t until_us);
    // Turns the per-firing duration measurement off, for benchmarks of the scheduler itself.
    void measure_durations(bool on) noexcept { measure_ = on; }
    // Under `valgrind --tool=callgrind --collect-atstart=no`, instructions are counted only while
    // this lane's systems run (callgrind's client requests; outside valgrind they do nothing): the
    // haptic tick alone, without the main lane's frame work the whole process's count carries.
    void count_instructions_of_lane(std::optional<std::size_t> lane) noexcept { counted_lane_ = lane; }
    // Duration of everything one lane ran at one timestamp (a "tick"), per lane.
    [[nodiscard]] const std::vector<DurationHistogram>& tick_ns() const noexcept { return tick_ns_; }

private:
    Schedule& schedule_;
    std::vector<DurationHistogram> tick_ns_;
    std::int64_t now_us_ = 0;
    bool measure_ = true;
    std::optional<std::size_t> counted_lane_;
};

struct LaneReport {
    std::uint64_t firings = 0;
    std::uint64_t clamp_events = 0;   // times the catch-up clamp dropped firings
    std::uint64_t skipped_firings = 0;
    DurationHistogram wake_lateness_ns; // how late the lane woke for each due time
    DurationHistogram tick_ns;          // from waking to the end of the last system due then
    bool fifo_priority = false;         // an own-thread lane got the real-time priority it asked for
    // Not empty: the lane threw this and stopped the run; every pushing device was sent zero force
    // (zeroed_devices of them) before the other lanes were stopped.
    std::string failure;
    std::size_t zeroed_devices = 0;
    // RealtimeConfig::lock_memory: whether the process's memory is locked (the same for every lane).
    bool memory_locked = false;
};

struct RealtimeConfig {
    // How far a lane may fall behind before the firings it missed are dropped.
    std::int64_t max_catchup_us = 50'000;
    // Requested timer slack for lanes with their own thread (Linux; 0 leaves the default).
    std::int64_t own_thread_timer_slack_ns = 1'000;
    // Lanes with their own thread ask for SCHED_FIFO at this priority (Linux; 0: normal scheduling).
    // On two cores the renderer's threads otherwise delay the 1 kHz loop's wake-ups by milliseconds.
    // The loop sleeps between ticks and its tick is tens of microseconds, so it cannot starve the
    // rest; without the privilege the request fails and the lane runs at normal priority.
    int own_thread_fifo_priority = 0;
    // Lock the process's memory (mlockall, pages locked as they are first touched) before the lanes
    // start, so that the 1 kHz lane's pages are never swapped out from under it. Asked only where it
    // cannot fail later (root, CAP_IPC_LOCK or no memlock limit: a limit reached by a later mapping,
    // the renderer's, would fail that mapping instead).
    bool lock_memory = false;
    // Told on the lane's own thread each time the clamp drops firings: the lane, its due time then
    // and the time its firings resume from (what DeterministicClock::skip_lane needs to do the same).
    std::function<void(std::size_t lane, std::int64_t due_us, std::int64_t until_us)> on_skip;
};

class RealtimeClock {
public:
    RealtimeClock(Schedule& schedule, RealtimeConfig config = {});

    // Runs for `seconds` of wall time, or until *stop becomes true (set by a window close, say), a
    // SIGINT or SIGTERM asks the program to stop (engine/core/emergency_stop.hpp), or a lane throws.
    // Returns one report per lane, in lane order; a lane's `failure` says it threw.
    std::vector<LaneReport> run_for(double seconds, const std::atomic<bool>* stop = nullptr);

private:
    Schedule& schedule_;
    RealtimeConfig config_;
};

} // namespace ikebana::sched
