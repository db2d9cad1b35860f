#include "engine/sched/schedule.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "engine/ecs/registry.hpp"

namespace ikebana::sched {

namespace {
// Sets the running system's access mask on the registry for one firing, and always clears it again.
class AccessScope {
public:
    AccessScope(ecs::Registry& r, const ecs::AccessMask* mask) : r_(r) { r_.set_access_mask(mask); }
    ~AccessScope() { r_.set_access_mask(nullptr); }
    AccessScope(const AccessScope&) = delete;
    AccessScope& operator=(const AccessScope&) = delete;

private:
    ecs::Registry& r_;
};

std::shared_ptr<const ecs::AccessMask> mask_of(const SystemDesc& d) {
    if (!d.checked) return nullptr;
    auto mask = std::make_shared<ecs::AccessMask>();
    mask->system = d.name;
    auto mark = [&](const std::vector<std::uint32_t>& ids, std::uint8_t level) {
        for (const auto id : ids) {
            if (id >= mask->by_type.size()) mask->by_type.resize(std::size_t{id} + 1, ecs::AccessMask::none);
            mask->by_type[id] = std::max(mask->by_type[id], level);
        }
    };
    mark(d.read_ids, ecs::AccessMask::read);
    mark(d.write_ids, ecs::AccessMask::write);
    mask->used.assign(mask->by_type.size(), ecs::AccessMask::none);
    return mask;
}
} // namespace

namespace {
thread_local const char* system_running = nullptr;
// Names the system this thread runs, for as long as it runs (and its queued changes are applied).
struct SystemTag {
    explicit SystemTag(const char* name) noexcept : previous(system_running) { system_running = name; }
    ~SystemTag() { system_running = previous; }
    SystemTag(const SystemTag&) = delete;
    SystemTag& operator=(const SystemTag&) = delete;
    const char* previous;
};
} // namespace

const char* running_system() noexcept { return system_running; }

void ScheduledSystem::fire(ecs::Registry& registry) {
    SystemContext ctx{registry, next_due_us, dt_s(), firing};
    const SystemTag tag(desc.name.c_str());
    {
        const AccessScope scope(registry, access.get());
        desc.run(ctx);
    }
    registry.commands().apply();
    ++firing;
    next_due_us = due_us(firing);
}

std::uint64_t ScheduledSystem::skip_until(std::int64_t t_us) {
    if (next_due_us >= t_us) return 0;
    // The first firing due at or after t, computed (a replay's recorded skip may span hours of 1 kHz
    // firings): k = t * rate, then corrected for the rounding of due_us.
    // (split as due_us is, so that no product overflows; the loops below make the floor a ceiling)
    const auto r = static_cast<std::uint64_t>(rate_mhz);
    const auto t = static_cast<std::uint64_t>(t_us);
    std::uint64_t k = (t / 1'000'000'000) * r + ((t % 1'000'000'000) * r) / 1'000'000'000;
    while (k > 0 && due_us(k - 1) >= t_us) --k;
    while (due_us(k) < t_us) ++k;
    const std::uint64_t skipped = k > firing ? k - firing : 0;
    firing = std::max(firing, k);
    next_due_us = due_us(firing);
    stats.skipped_firings += skipped;
    return skipped;
}

Schedule::Schedule(RateTable rates) : rates_(std::move(rates)) {}
Schedule::~Schedule() = default;

Result<void> Schedule::add_lane(LaneDesc lane) {
    if (finalized_) return make_error(ErrorCode::invalid_argument, "add_lane after finalize()");
    if (!lane.registry) return make_error(ErrorCode::invalid_argument, "lane '" + lane.name + "' has no registry");
    for (const auto& existing : lanes_) {
        if (existing.name == lane.name) return make_error(ErrorCode::invalid_argument, "lane '" + lane.name + "' added twice");
    }
    if (lane.phases.empty()) return make_error(ErrorCode::invalid_argument, "lane '" + lane.name + "' has no phases");
    lanes_.push_back(std::move(lane));
    return {};
}

Result<void> Schedule::add(SystemDesc system) {
    if (finalized_) return make_error(ErrorCode::invalid_argument, "system '" + system.name + "' added after finalize()");
    if (system.name.empty()) return make_error(ErrorCode::invalid_argument, "a system needs a name");
    if (!system.run) return make_error(ErrorCode::invalid_argument, "system '" + system.name + "' has no function");
    for (const auto& s : pending_) {
        if (s.name == system.name) return make_error(ErrorCode::invalid_argument, "system '" + system.name + "' registered twice");
    }
    const auto lane = std::find_if(lanes_.begin(), lanes_.end(), [&](const LaneDesc& l) { return l.name == system.lane; });
    if (lane == lanes_.end()) {
        return make_error(ErrorCode::not_found, "system '" + system.name + "': unknown lane '" + system.lane + "'");
    }
    if (std::find(lane->phases.begin(), lane->phases.end(), system.phase) == lane->phases.end()) {
        return make_error(ErrorCode::not_found, "system '" + system.name + "': lane '" + system.lane +
                                                    "' has no phase '" + system.phase + "'");
    }
    if (!rates_.contains(system.rate)) {
        return make_error(ErrorCode::not_found, "system '" + system.name + "': unknown rate '" + system.rate +
                                                    "' (known: " + rates_.names() + ")");
    }
    system.module = module_;
    pending_.push_back(std::move(system));
    return {};
}

void Schedule::begin_module(std::string name) {
    if (std::find(modules_.begin(), modules_.end(), name) == modules_.end()) modules_.push_back(name);
    module_ = std::move(name);
}

Result<void> Schedule::finalize() {
    if (finalized_) return {};
    // Group by (lane, phase) in declared order, keeping registration order inside a group.
    std::vector<ScheduledSystem> ordered;
    std::vector<std::string> problems;
    for (std::size_t li = 0; li < lanes_.size(); ++li) {
        for (const auto& phase : lanes_[li].phases) {
            std::vector<const SystemDesc*> group;
            for (const auto& s : pending_) {
                if (s.lane == lanes_[li].name && s.phase == phase) group.push_back(&s);
            }
            // `after` edges: every name must be a system of the same phase (an edge across phases or
            // lanes is meaningless: phases are already ordered, lanes are separate worlds).
            std::map<std::string, std::size_t> index;
            for (std::size_t i = 0; i < group.size(); ++i) index[group[i]->name] = i;
            std::vector<std::vector<std::size_t>> preds(group.size());
            for (std::size_t i = 0; i < group.size(); ++i) {
                for (const auto& a : group[i]->after) {
                    auto it = index.find(a);
                    if (it == index.end()) {
                        problems.push_back("system '" + group[i]->name + "' is ordered after '" + a +
                                           "', which is not a system of phase '" + phase + "'");
                    } else {
                        preds[i].push_back(it->second);
                    }
                }
            }
            // Reachability, for "is there an order between these two?" (groups are small).
            const std::size_t n = group.size();
            std::vector<std::vector<bool>> before(n, std::vector<bool>(n, false)); // before[i][j]: j runs before i
            auto reach = [&] {
                for (std::size_t i = 0; i < n; ++i) {
                    std::fill(before[i].begin(), before[i].end(), false);
                    std::vector<std::size_t> stack(preds[i].begin(), preds[i].end());
                    while (!stack.empty()) {
                        const auto j = stack.back();
                        stack.pop_back();
                        if (before[i][j]) continue;
                        before[i][j] = true;
                        for (const auto k : preds[j]) stack.push_back(k);
                    }
                }
            };
            reach();
            // Module order: a conflict between two modules' systems with no explicit order is settled by
            // the order the modules were installed in.
            auto module_rank = [&](const SystemDesc& d) -> std::ptrdiff_t {
                const auto it = std::find(modules_.begin(), modules_.end(), d.module);
                return d.module.empty() || it == modules_.end() ? -1 : it - modules_.begin();
            };
            auto conflicting = [](const SystemDesc& a, const SystemDesc& b) {
                auto meets = [](const std::vector<std::string>& x, const std::vector<std::string>& y) {
                    return std::any_of(x.begin(), x.end(), [&](const std::string& c) { return std::find(y.begin(), y.end(), c) != y.end(); });
                };
                return meets(a.writes, b.writes) || meets(a.writes, b.reads) || meets(b.writes, a.reads);
            };
            bool added = false;
            for (std::size_t i = 0; i < n; ++i) {
                for (std::size_t j = 0; j < n; ++j) {
                    const auto ri = module_rank(*group[i]);
                    const auto rj = module_rank(*group[j]);
                    if (ri < 0 || rj < 0 || rj >= ri || before[i][j] || before[j][i]) continue;
                    if (!conflicting(*group[i], *group[j])) continue;
                    preds[i].push_back(j); // j's module was installed first
                    added = true;
                }
            }
            if (added) reach();
            for (std::size_t i = 0; i < n; ++i) {
                if (before[i][i]) problems.push_back("systems of phase '" + phase + "' are ordered in a cycle through '" + group[i]->name + "'");
            }
            // Conflicts: a write meeting a read or a write of the same component, with no order.
            for (std::size_t i = 0; i < n; ++i) {
                for (std::size_t j = i + 1; j < n; ++j) {
                    if (before[i][j] || before[j][i]) continue;
                    const auto& a = *group[i];
                    const auto& b = *group[j];
                    auto clash = [&](const std::vector<std::string>& w, const std::vector<std::string>& other, const char* kind) {
                        for (const auto& c : w) {
                            if (std::find(other.begin(), other.end(), c) != other.end()) {
                                problems.push_back("systems '" + a.name + "' and '" + b.name + "' in phase '" + phase + "' " +
                                                   kind + " '" + c + "' with no order between them (add `after`)");
                            }
                        }
                    };
                    clash(a.writes, b.writes, "both write");
                    clash(a.writes, b.reads, "write/read");
                    clash(b.writes, a.reads, "write/read");
                }
            }
            // Kahn's algorithm, smallest registration index first, so the order is stable.
            std::vector<std::size_t> indegree(n, 0);
            for (std::size_t i = 0; i < n; ++i) indegree[i] = preds[i].size();
            std::set<std::size_t> ready;
            for (std::size_t i = 0; i < n; ++i) {
                if (indegree[i] == 0) ready.insert(i);
            }
            std::vector<bool> placed(n, false);
            while (!ready.empty()) {
                const auto i = *ready.begin();
                ready.erase(ready.begin());
                placed[i] = true;
                ScheduledSystem s;
                s.desc = *group[i];
                s.lane = li;
                s.access = mask_of(s.desc);
                ordered.push_back(std::move(s));
                for (std::size_t k = 0; k < n; ++k) {
                    if (!placed[k] && std::count(preds[k].begin(), preds[k].end(), i) > 0) {
                        indegree[k] -= static_cast<std::size_t>(std::count(preds[k].begin(), preds[k].end(), i));
                        if (indegree[k] == 0) ready.insert(k);
                    }
                }
            }
        }
    }
    if (!problems.empty()) {
        std::string message = "the schedule is inconsistent:";
        for (const auto& p : problems) message += "\n  - " + p;
        return make_error(ErrorCode::schedule_conflict, message);
    }
    for (auto& s : ordered) {
        s.rate_mhz = std::llround(rates_.hz(s.desc.rate) * 1000.0);
        s.firing = 0;
        s.next_due_us = 0;
    }
    systems_ = std::move(ordered);
    pending_.clear();
    finalized_ = true;
    return {};
}

const ScheduledSystem* Schedule::find(std::string_view name) const {
    for (const auto& s : systems_) {
        if (s.desc.name == name) return &s;
    }
    return nullptr;
}

std::vector<std::string> Schedule::unused_access() const {
    std::vector<std::string> out;
    for (const auto& s : systems_) {
        if (!s.access || s.firing == 0) continue;
        const auto& used = s.access->used;
        const auto level = [&](std::uint32_t id) { return id < used.size() ? used[id] : std::uint8_t{ecs::AccessMask::none}; };
        const auto& d = s.desc;
        for (std::size_t i = 0; i < d.write_ids.size(); ++i) {
            const auto got = level(d.write_ids[i]);
            if (got == ecs::AccessMask::write) continue;
            out.push_back("system '" + d.name + "' declares writing '" + d.writes[i] + "' and " +
                          (got == ecs::AccessMask::read ? "only reads it" : "never touches it"));
        }
        for (std::size_t i = 0; i < d.read_ids.size(); ++i) {
            if (std::find(d.write_ids.begin(), d.write_ids.end(), d.read_ids[i]) != d.write_ids.end()) continue;
            if (level(d.read_ids[i]) == ecs::AccessMask::none) out.push_back("system '" + d.name + "' declares reading '" + d.reads[i] + "' and never reads it");
        }
    }
    return out;
}

std::string Schedule::stats_table() const {
    std::ostringstream out;
    char line[256];
    std::snprintf(line, sizeof line, "%-28s %-7s %9s %10s %10s %10s %10s %10s %8s %8s\n", "system", "lane", "rate_hz",
                  "calls", "mean_us", "p99_us", "max_us", "late_p99", "missed", "skipped");
    out << line;
    for (const auto& s : systems_) {
        const auto& st = s.stats;
        std::snprintf(line, sizeof line, "%-28s %-7s %9.2f %10llu %10.2f %10.2f %10.2f %10.2f %8llu %8llu\n",
                      s.desc.name.c_str(), lanes_[s.lane].name.c_str(), static_cast<double>(s.rate_mhz) / 1000.0,
                      static_cast<unsigned long long>(st.calls), st.duration_ns.mean() / 1e3,
                      static_cast<double>(st.duration_ns.percentile(0.99)) / 1e3,
                      static_cast<double>(st.duration_ns.max()) / 1e3,
                      static_cast<double>(st.lateness_ns.percentile(0.99)) / 1e3,
                      static_cast<unsigned long long>(st.missed_deadlines),
                      static_cast<unsigned long long>(st.skipped_firings));
        out << line;
    }
    return out.str();
}

} // namespace ikebana::sched
