#include "engine/sched/clocks.hpp"

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define IKEBANA_HAS_CALLGRIND 1
#else
#define IKEBANA_HAS_CALLGRIND 0
#endif

#include <algorithm>
#include <chrono>
#include <ctime>
#include <limits>
#include <exception>
#include <stdexcept>
#include <thread>

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include "engine/core/emergency_stop.hpp"
#include "engine/core/monotonic_clock.hpp"
#include "engine/ecs/registry.hpp"

namespace ikebana::sched {

namespace {

// Sleeps until an absolute point of CLOCK_MONOTONIC, so that lateness in one tick never shifts the
// deadlines after it.
void sleep_until_ns(std::int64_t deadline_ns) {
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(deadline_ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(deadline_ns % 1'000'000'000);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}

thread_local const char* lane_running = nullptr;

// Names the lane whose system this thread runs, for as long as it runs.
class LaneTag {
public:
    explicit LaneTag(const char* lane) noexcept : previous_(lane_running) { lane_running = lane; }
    ~LaneTag() { lane_running = previous_; }
    LaneTag(const LaneTag&) = delete;
    LaneTag& operator=(const LaneTag&) = delete;

private:
    const char* previous_;
};

std::int64_t next_due(const std::vector<ScheduledSystem*>& systems) {
    std::int64_t t = std::numeric_limits<std::int64_t>::max();
    for (const auto* s : systems) t = std::min(t, s->next_due_us);
    return t;
}

} // namespace

const char* running_lane() noexcept { return lane_running; }

DeterministicClock::DeterministicClock(Schedule& schedule) : schedule_(schedule) {
    if (!schedule_.finalized()) throw std::logic_error("DeterministicClock needs a finalized schedule");
}

namespace {
// Callgrind's collection, on or off (a no-op outside valgrind, and where its header is missing).
void toggle_instruction_count() {
#if IKEBANA_HAS_CALLGRIND
    CALLGRIND_TOGGLE_COLLECT;
#endif
}
} // namespace

void DeterministicClock::run_until(std::int64_t t_us) {
    auto& systems = schedule_.systems();
    const auto& lanes = schedule_.lanes();
    if (systems.empty()) {
        now_us_ = std::max(now_us_, t_us);
        return;
    }
    for (;;) {
        std::int64_t t = std::numeric_limits<std::int64_t>::max();
        for (const auto& s : systems) t = std::min(t, s.next_due_us);
        if (t >= t_us) break;
        now_us_ = t;
        if (tick_ns_.size() < lanes.size()) tick_ns_.resize(lanes.size());
        std::vector<std::int64_t> lane_ns(measure_ ? lanes.size() : 0, 0);
        std::vector<bool> lane_ran(measure_ ? lanes.size() : 0, false);
        // `systems` is already in tie-break order (lane, phase, after, registration).
        for (auto& s : systems) {
            if (s.next_due_us != t) continue;
            const bool counted = counted_lane_ && *counted_lane_ == s.lane;
            if (counted) toggle_instruction_count();
            const LaneTag tag(lanes[s.lane].name.c_str());
            if (measure_) {
                const auto begin = monotonic_ns();
                s.fire(*lanes[s.lane].registry);
                const std::int64_t took = monotonic_ns() - begin;
                s.stats.duration_ns.record(took);
                lane_ns[s.lane] += took;
                lane_ran[s.lane] = true;
            } else {
                s.fire(*lanes[s.lane].registry);
            }
            if (counted) toggle_instruction_count();
            ++s.stats.calls;
        }
        for (std::size_t li = 0; li < lane_ns.size(); ++li) {
            if (lane_ran[li]) tick_ns_[li].record(lane_ns[li]);
        }
    }
    now_us_ = t_us;
}

DeterministicClock::Moment DeterministicClock::moment() const {
    Moment m;
    m.now_us = now_us_;
    for (const auto& s : schedule_.systems()) m.firings.emplace_back(s.firing, s.next_due_us);
    return m;
}

bool DeterministicClock::resume_from(const Moment& m) {
    auto& systems = schedule_.systems();
    if (m.firings.size() != systems.size()) return false;
    for (std::size_t i = 0; i < systems.size(); ++i) {
        systems[i].firing = m.firings[i].first;
        systems[i].next_due_us = m.firings[i].second;
    }
    now_us_ = m.now_us;
    return true;
}

void DeterministicClock::skip_lane(std::size_t lane, std::int64_t until_us) {
    for (auto& s : schedule_.systems()) {
        if (s.lane == lane) s.skip_until(until_us);
    }
}

RealtimeClock::RealtimeClock(Schedule& schedule, RealtimeConfig config) : schedule_(schedule), config_(config) {
    if (!schedule_.finalized()) throw std::logic_error("RealtimeClock needs a finalized schedule");
}

std::vector<LaneReport> RealtimeClock::run_for(double seconds, const std::atomic<bool>* external_stop) {
    const auto& lanes = schedule_.lanes();
    std::vector<std::vector<ScheduledSystem*>> by_lane(lanes.size());
    for (auto& s : schedule_.systems()) by_lane[s.lane].push_back(&s);
    std::vector<LaneReport> reports(lanes.size());

    // Each lane continues its own timeline from where it stands; t0 maps the earliest due time to now.
    std::int64_t earliest = std::numeric_limits<std::int64_t>::max();
    for (const auto& lane : by_lane) earliest = std::min(earliest, next_due(lane));
    if (earliest == std::numeric_limits<std::int64_t>::max()) earliest = 0;
    const std::int64_t start_ns = monotonic_ns() - earliest * 1000;
    const std::int64_t end_us = earliest + static_cast<std::int64_t>(seconds * 1e6);
    std::atomic<bool> lanes_stop{false};

    auto run_lane_unguarded = [&](std::size_t li) {
        auto& systems = by_lane[li];
        auto& report = reports[li];
        ecs::Registry& registry = *lanes[li].registry;
        for (;;) {
            if (lanes_stop.load(std::memory_order_relaxed)) break;
            if (external_stop && external_stop->load(std::memory_order_relaxed)) break;
            if (stop_requested()) break; // SIGINT, SIGTERM: the caller ends the ordinary way
            const std::int64_t t = next_due(systems);
            if (t >= end_us) break;
            const std::int64_t deadline_ns = start_ns + t * 1000;
            sleep_until_ns(deadline_ns);
            const std::int64_t woke_ns = monotonic_ns();
            report.wake_lateness_ns.record(woke_ns - deadline_ns);
            const std::int64_t now_us = (woke_ns - start_ns) / 1000;
            if (now_us - t > config_.max_catchup_us) {
                // Far behind (a stall, a debugger, a swapped-out process): drop what is too old.
                ++report.clamp_events;
                for (auto* s : systems) report.skipped_firings += s->skip_until(now_us - config_.max_catchup_us);
                if (config_.on_skip) config_.on_skip(li, t, now_us - config_.max_catchup_us);
                continue;
            }
            for (auto* s : systems) {
                if (s->next_due_us != t) continue;
                const std::int64_t begin = monotonic_ns();
                const std::int64_t lateness = begin - deadline_ns;
                s->stats.lateness_ns.record(lateness);
                const std::int64_t period_ns = (s->due_us(s->firing + 1) - s->next_due_us) * 1000;
                if (lateness > period_ns) ++s->stats.missed_deadlines;
                const LaneTag tag(lanes[li].name.c_str());
                s->fire(registry);
                s->stats.duration_ns.record(monotonic_ns() - begin);
                ++s->stats.calls;
                ++report.firings;
            }
            report.tick_ns.record(monotonic_ns() - woke_ns);
        }
    };

    // An exception on a lane (an undeclared access, a logic error) would otherwise end in std::terminate
    // with the force still on: every pushing device is zeroed at once, every lane stops, and the
    // report says which lane and why.
    auto run_lane = [&](std::size_t li) {
        try {
            run_lane_unguarded(li);
        } catch (const std::exception& e) {
            reports[li].failure = e.what();
        } catch (...) {
            reports[li].failure = "an exception of unknown type";
        }
        if (!reports[li].failure.empty()) {
            lanes_stop.store(true);
            reports[li].zeroed_devices = run_emergency_stops();
        }
    };

    if (config_.lock_memory) {
        rlimit limit{};
        const bool unlimited = getrlimit(RLIMIT_MEMLOCK, &limit) == 0 && limit.rlim_cur == RLIM_INFINITY;
        const bool locked = (unlimited || geteuid() == 0) && mlockall(MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT) == 0;
        for (auto& r : reports) r.memory_locked = locked;
    }
    std::vector<std::thread> threads;
    for (std::size_t li = 0; li < lanes.size(); ++li) {
        if (lanes[li].thread != LaneThread::own) continue;
        threads.emplace_back([&, li] {
            if (config_.own_thread_timer_slack_ns > 0) prctl(PR_SET_TIMERSLACK, config_.own_thread_timer_slack_ns);
            if (config_.own_thread_fifo_priority > 0) {
                sched_param param{};
                param.sched_priority = config_.own_thread_fifo_priority;
                reports[li].fifo_priority = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
            }
            run_lane(li);
        });
    }
    for (std::size_t li = 0; li < lanes.size(); ++li) {
        if (lanes[li].thread == LaneThread::caller) run_lane(li);
    }
    // The caller's lanes are done. If that was a stop request (a window closed), stop the other lanes
    // now; if time ran out, they finish their own timeline up to the same end.
    if ((external_stop && external_stop->load()) || stop_requested()) lanes_stop.store(true);
    for (auto& t : threads) t.join();
    return reports;
}

} // namespace ikebana::sched
