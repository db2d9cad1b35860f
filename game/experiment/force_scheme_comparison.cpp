#include "game/experiment/force_scheme_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "components/hand.hpp"
#include "engine/sched/clocks.hpp"
#include "game/scene/scene.hpp"
#include "game/world/world.hpp"

namespace ikebana::game {

namespace {

Result<std::array<std::vector<glm::dvec3>, 2>> run(const SceneDef& scene, const std::string& scheme, double seconds) {
    auto world = World::create(scene, WorldOptions{.rate_overrides = {}, .force_scheme = scheme, .main_lane_systems = {}});
    if (!world) return std::move(world).error();
    auto* log = (*world)->sim.resource<components::SentForceLog>();
    log->enabled = true;
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(static_cast<std::int64_t>(seconds * 1e6));
    return std::array<std::vector<glm::dvec3>, 2>{log->hand[0], log->hand[1]};
}

SchemeFigures figures(const std::vector<glm::dvec3>& f, const std::vector<glm::dvec3>& reference) {
    SchemeFigures out;
    std::vector<double> jumps;
    for (std::size_t i = 1; i < f.size(); ++i) jumps.push_back(glm::length(f[i] - f[i - 1]));
    if (!jumps.empty()) {
        out.max_jump_n = *std::max_element(jumps.begin(), jumps.end());
        std::sort(jumps.begin(), jumps.end());
        out.p99_jump_n = jumps[static_cast<std::size_t>(0.99 * static_cast<double>(jumps.size() - 1))];
    }
    double sum = 0.0;
    const std::size_t n = std::min(f.size(), reference.size());
    for (std::size_t i = 0; i < n; ++i) sum += glm::dot(f[i] - reference[i], f[i] - reference[i]);
    out.rms_error_n = n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
    return out;
}

// The delay (in ticks) that best aligns `late` with `reference`: argmin over k of the mean squared
// difference between late[t] and reference[t - k].
double best_lag_ticks(const std::vector<glm::dvec3>& late, const std::vector<glm::dvec3>& reference, int max_lag) {
    double best = std::numeric_limits<double>::infinity();
    int best_k = 0;
    for (int k = 0; k <= max_lag; ++k) {
        double sum = 0.0;
        std::size_t n = 0;
        for (std::size_t t = static_cast<std::size_t>(k); t < std::min(late.size(), reference.size()); ++t) {
            const glm::dvec3 d = late[t] - reference[t - static_cast<std::size_t>(k)];
            sum += glm::dot(d, d);
            ++n;
        }
        if (n > 0 && sum / static_cast<double>(n) < best) {
            best = sum / static_cast<double>(n);
            best_k = k;
        }
    }
    return best_k;
}

} // namespace

Result<std::vector<ForceSchemeComparison>> compare_force_schemes(const std::string& scene_file, double seconds) {
    auto scene = load_scene(scene_file);
    if (!scene) return std::move(scene).error();
    auto full = run(*scene, "full_rate", seconds);
    if (!full) return std::move(full).error();
    auto paper = run(*scene, "paper", seconds);
    if (!paper) return std::move(paper).error();
    std::vector<ForceSchemeComparison> out;
    for (int h = 0; h < 2; ++h) {
        const auto& f = (*full)[static_cast<std::size_t>(h)];
        const auto& p = (*paper)[static_cast<std::size_t>(h)];
        if (f.empty() || std::all_of(f.begin(), f.end(), [](const glm::dvec3& v) { return v == glm::dvec3{0.0}; })) continue;
        ForceSchemeComparison c;
        c.hand = h;
        c.full_rate = figures(f, f);
        c.paper = figures(p, f);
        c.paper_lag_ms = best_lag_ticks(p, f, 200);
        double sum = 0.0;
        for (const auto& v : f) sum += glm::length(v);
        c.mean_force_n = sum / static_cast<double>(f.size());
        out.push_back(c);
    }
    return out;
}

std::string format_force_comparison(const std::vector<ForceSchemeComparison>& result) {
    std::string out = "hand   scheme      largest jump/tick   p99 jump/tick   RMS error vs full rate   lag\n";
    char line[256];
    for (const auto& c : result) {
        std::snprintf(line, sizeof line, "%-6s full rate   %14.4f N   %11.4f N   %20s   %s\n", c.hand ? "right" : "left",
                      c.full_rate.max_jump_n, c.full_rate.p99_jump_n, "-", "-");
        out += line;
        std::snprintf(line, sizeof line, "%-6s paper       %14.4f N   %11.4f N   %18.4f N   %.0f ms\n", "", c.paper.max_jump_n,
                      c.paper.p99_jump_n, c.paper.rms_error_n, c.paper_lag_ms);
        out += line;
        if (c.full_rate.p99_jump_n > 0.0) {
            std::snprintf(line, sizeof line, "       -> the paper scheme's p99 jump is %.1fx the full-rate one's (mean force %.3f N)\n",
                          c.paper.p99_jump_n / c.full_rate.p99_jump_n, c.mean_force_n);
            out += line;
        }
    }
    return out;
}

} // namespace ikebana::game
