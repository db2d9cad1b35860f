#pragma once
// The schedule: lanes (one world each; a lane may get its own thread in real time), their phases in
// order, and the systems in them. finalize() fixes the execution order and refuses conflicting access
// before anything runs.
//
// Order at equal timestamps (the documented tie-break): lanes in the order they were added, then
// phases in their declared order, then systems ordered by `after` constraints, then by module (below),
// then registration order.
//
// Modules (flecs' modules, Bevy's plugins): each systems folder installs its own systems between
// begin_module() and end_module(). Two systems of different modules whose access conflicts in one phase
// run in the order their modules were installed, so modules are ordered, not single systems; inside a
// module a conflict still needs an explicit `after`.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/result.hpp"
#include "engine/ecs/fwd.hpp"
#include "engine/sched/rates.hpp"
#include "engine/sched/stats.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::sched {

enum class LaneThread {
    caller, // runs on the thread that drives the clock (the main thread: rendering, UI)
    own,    // gets a dedicated thread on the real-time clock (the 1 kHz haptic loop)
};

struct LaneDesc {
    std::string name;
    ecs::Registry* registry = nullptr;
    LaneThread thread = LaneThread::caller;
    std::vector<std::string> phases;
};

// One system as scheduled: its description plus its place on the integer-microsecond timeline.
struct ScheduledSystem {
    SystemDesc desc;
    std::size_t lane = 0;
    std::int64_t rate_mhz = 0;  // the rate in millihertz, so that due times are exact integers
    std::uint64_t firing = 0;   // index of the next firing
    std::int64_t next_due_us = 0;
    SystemStats stats;
    std::shared_ptr<const ecs::AccessMask> access; // what the registry holds the system to; null: unchecked

    // Firing k is due at floor(k / rate) seconds, in microseconds: no drift over any run length, and
    // rates need not divide each other.
    [[nodiscard]] std::int64_t due_us(std::uint64_t k) const noexcept {
        // Split so the product cannot overflow: (k mod rate) * 1e9 < 1e17 for any supported rate.
        const auto r = static_cast<std::uint64_t>(rate_mhz);
        return static_cast<std::int64_t>((k / r) * 1'000'000'000 + ((k % r) * 1'000'000'000) / r);
    }
    // The span this firing advances over, [due(k), due(k+1)): summed over N firings it is exactly
    // due(N), so integrators never gain or lose time.
    [[nodiscard]] double dt_s() const noexcept {
        return static_cast<double>(due_us(firing + 1) - next_due_us) * 1e-6;
    }
    // Runs the system once at its due time and moves to the next firing. Applies the lane's
    // command buffer afterwards: the defined point where deferred structural changes land.
    void fire(ecs::Registry& registry);
    // Skips firings due before `t_us` without running them (the catch-up clamp); returns how many.
    std::uint64_t skip_until(std::int64_t t_us);
};

class Schedule {
public:
    explicit Schedule(RateTable rates = RateTable::paper_defaults());
    Schedule(const Schedule&) = delete;
    Schedule& operator=(const Schedule&) = delete;
    ~Schedule();

    Result<void> add_lane(LaneDesc lane);
    // Fails on an unknown lane, phase or rate, a duplicate name, or a missing function.
    Result<void> add(SystemDesc system);
    // Systems added until end_module() belong to `name`; modules are ordered by their first beginning.
    void begin_module(std::string name);
    void end_module() { module_.clear(); }

    [[nodiscard]] RateTable& rates() noexcept { return rates_; }
    // Checks access conflicts and `after` references, fixes the order and the timeline.
    // Any earlier rate change takes effect here.
    Result<void> finalize();
    [[nodiscard]] bool finalized() const noexcept { return finalized_; }

    [[nodiscard]] const std::vector<LaneDesc>& lanes() const noexcept { return lanes_; }
    // Systems in execution order (valid after finalize()).
    [[nodiscard]] std::vector<ScheduledSystem>& systems() noexcept { return systems_; }
    [[nodiscard]] const std::vector<ScheduledSystem>& systems() const noexcept { return systems_; }
    [[nodiscard]] const ScheduledSystem* find(std::string_view name) const;

    // Over-declaring, as found by running: for each checked system that has fired, every type it declared
    // and never touched, and every type it declared written and only read, one sentence each (empty:
    // every declaration was used). A declaration wider than the body orders systems that need no order
    // and hides the access that matters; the reverse, an undeclared access, throws as it happens.
    [[nodiscard]] std::vector<std::string> unused_access() const;

    // A table of per-system statistics for --stats.
    [[nodiscard]] std::string stats_table() const;

private:
    RateTable rates_;
    std::vector<LaneDesc> lanes_;
    std::vector<SystemDesc> pending_;
    std::vector<std::string> modules_; // in installation order
    std::string module_;
    std::vector<ScheduledSystem> systems_;
    bool finalized_ = false;
};

} // namespace ikebana::sched
