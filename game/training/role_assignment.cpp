#include "game/training/role_assignment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "game/training/form_text.hpp"
#include "game/training/stem_geometry.hpp"

namespace ikebana::game::training {

namespace {

struct RoleCost {
    double cost = 0.0;
    bool allowed = true;
};

// How far a stem is from a role's bands (in bands), for choosing who plays which role.
RoleCost role_cost(const LessonDef& l, std::size_t role, const ArrangementStem& s, const KenzanFootprint& k) {
    const MainStemDef& m = l.stems[role];
    if (!m.species.empty() && std::find(m.species.begin(), m.species.end(), s.species) == m.species.end()) return {0.0, false};
    const double nominal = nominal_length_m(l, role);
    const double length_band = std::max(1e-3, m.length_ratio.tolerance / std::max(1e-9, m.length_ratio.target) * nominal);
    double cost = std::abs(s.length_m - nominal) / length_band;
    for (const double other : m.length_also) cost = std::min(cost, std::abs(s.length_m - nominal * other / m.length_ratio.target) / length_band);
    cost += std::abs(s.tilt_rad - m.tilt_rad.target) / std::max(deg, m.tilt_rad.tolerance);
    if (m.azimuth_rad) cost += std::abs(wrap_deg((s.azimuth_rad - m.azimuth_rad->target) / deg)) * deg / std::max(deg, m.azimuth_rad->tolerance);
    cost += outside_region(s.base_m, m.region, k.size_m) / 0.004;
    return {cost, true};
}

constexpr double inf = std::numeric_limits<double>::infinity();

// The free stems' roles by the least total cost (roles taken already are not open); the set of roles
// they fill, as a mask.
std::size_t assign_standing(const LessonDef& l, Arrangement& a, const std::vector<std::size_t>& free_stems, const std::vector<bool>& taken,
                            const KenzanFootprint& k) {
    const std::size_t n_roles = l.stems.size();
    const std::size_t masks = std::size_t{1} << n_roles;
    const double unfilled = 1e6; // a role left empty costs more than any stem in it
    // best[i][mask]: the least cost with the first i free stems placed and `mask` roles filled by them.
    std::vector<std::vector<double>> best(free_stems.size() + 1, std::vector<double>(masks, inf));
    std::vector<std::vector<int>> choice(free_stems.size() + 1, std::vector<int>(masks, -1));
    best[0][0] = 0.0;
    for (std::size_t i = 0; i < free_stems.size(); ++i) {
        for (std::size_t mask = 0; mask < masks; ++mask) {
            if (best[i][mask] == inf) continue;
            // The stem supports (no role) ...
            if (best[i][mask] < best[i + 1][mask]) {
                best[i + 1][mask] = best[i][mask];
                choice[i + 1][mask] = -1;
            }
            // ... or plays a role still open.
            for (std::size_t r = 0; r < n_roles; ++r) {
                if (taken[r] || (mask & (std::size_t{1} << r))) continue;
                const RoleCost rc = role_cost(l, r, a.stems[free_stems[i]], k);
                if (!rc.allowed) continue;
                const std::size_t next = mask | (std::size_t{1} << r);
                if (best[i][mask] + rc.cost < best[i + 1][next]) {
                    best[i + 1][next] = best[i][mask] + rc.cost;
                    choice[i + 1][next] = static_cast<int>(r);
                }
            }
        }
    }
    std::size_t best_mask = 0;
    double best_total = inf;
    for (std::size_t mask = 0; mask < masks; ++mask) {
        const double total = best[free_stems.size()][mask] + unfilled * static_cast<double>(n_roles - static_cast<std::size_t>(__builtin_popcountll(mask)));
        if (total < best_total) {
            best_total = total;
            best_mask = mask;
        }
    }
    // Walk back: which role each free stem took.
    std::size_t mask = best_mask;
    for (std::size_t i = free_stems.size(); i > 0; --i) {
        // choice[i][mask] is how the best way into (i, mask) came: the role stem i-1 took, or -1 (it supports).
        const int r = choice[i][mask];
        if (r >= 0) {
            a.stems[free_stems[i - 1]].role = l.stems[static_cast<std::size_t>(r)].role;
            mask &= ~(std::size_t{1} << r);
        } else {
            a.stems[free_stems[i - 1]].role = "supporting";
        }
    }
    return best_mask;
}

// A role no standing stem plays goes to the fallen stem nearest to it, so that its tips say it fell
// rather than that nothing plays it.
void assign_fallen(const LessonDef& l, Arrangement& a, const std::vector<bool>& taken, std::size_t filled, const KenzanFootprint& k) {
    for (std::size_t r = 0; r < l.stems.size(); ++r) {
        if (taken[r] || (filled & (std::size_t{1} << r))) continue;
        std::optional<std::size_t> nearest;
        double least = inf;
        for (std::size_t i = 0; i < a.stems.size(); ++i) {
            if (!a.stems[i].role.empty() || a.stems[i].standing) continue;
            const RoleCost rc = role_cost(l, r, a.stems[i], k);
            if (rc.allowed && rc.cost < least) {
                least = rc.cost;
                nearest = i;
            }
        }
        if (nearest) a.stems[*nearest].role = l.stems[r].role;
    }
}

} // namespace

Result<void> check_given_roles(const LessonDef& l, const Arrangement& a, const std::string& label) {
    const auto& stems = a.stems;
    std::string roles = "";
    for (const auto& m : l.stems) roles += m.role + ", ";
    for (std::size_t i = 0; i < stems.size(); ++i) {
        const std::string& role = stems[i].role;
        if (role.empty() || role == "supporting") continue;
        const auto it = std::find_if(l.stems.begin(), l.stems.end(), [&](const MainStemDef& m) { return m.role == role; });
        if (it == l.stems.end()) {
            return make_error(ErrorCode::invalid_argument,
                              fmt("%s: /stems/%zu/role: \"%s\" is not a role of %s (%sor supporting)", label.c_str(), i, role.c_str(), l.id.c_str(), roles.c_str()));
        }
        for (std::size_t j = 0; j < i; ++j) {
            if (stems[j].role == role) {
                return make_error(ErrorCode::invalid_argument, fmt("%s: /stems/%zu/role: \"%s\" is already played by /stems/%zu", label.c_str(), i, role.c_str(), j));
            }
        }
    }
    return Ok{};
}

void assign_roles(const LessonDef& l, Arrangement& a, const KenzanFootprint& k) {
    std::vector<bool> taken(l.stems.size(), false);
    for (const auto& s : a.stems) {
        for (std::size_t r = 0; r < l.stems.size(); ++r) {
            if (s.role == l.stems[r].role) taken[r] = true;
        }
    }
    std::vector<std::size_t> free_stems;
    for (std::size_t i = 0; i < a.stems.size(); ++i) {
        if (a.stems[i].role.empty() && a.stems[i].standing) free_stems.push_back(i);
    }
    const std::size_t filled = assign_standing(l, a, free_stems, taken, k);
    assign_fallen(l, a, taken, filled, k);
    for (auto& s : a.stems) {
        if (s.role.empty()) s.role = "supporting"; // fallen stems no role is missing
    }
}

std::vector<const ArrangementStem*> stems_by_role(const LessonDef& l, const Arrangement& a) {
    std::vector<const ArrangementStem*> by_role(l.stems.size(), nullptr);
    for (const auto& s : a.stems) {
        for (std::size_t r = 0; r < l.stems.size(); ++r) {
            if (s.role == l.stems[r].role) by_role[r] = &s;
        }
    }
    return by_role;
}

} // namespace ikebana::game::training
