// The haptic tick and the stem step it is made of (issue 16). Run: build/release/tests/bench/tick_bench
//  - BM_ArrangementTick: one 1 ms tick of assets/scenes/arrangement.json (ten flowers standing in the
//    400-pin kenzan, one lying, two scripted hands) after a second of settling: everything due.
//  - BM_StemStep/N: one implicit step of a clamped sunflower stem of N segments (linear in N).
//  - BM_ChainMillisecond/implicit and /explicit: one simulated millisecond of the same clamped
//    sunflower stem, by our step (once) and by an explicit chain (symplectic Euler on the same forces,
//    as CHAI3D's GEL does) in as many substeps as its stability limit needs; the limit is searched
//    first (the largest step that stays bounded for 0.2 s, within 2 %) and printed as a counter.
// Instructions (load-independent) for the last two: run under callgrind and read the inclusive counts
// of implicit_millisecond and explicit_millisecond (docs/benchmarks.md has the command).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "engine/sched/clocks.hpp"
#include "game/asset_paths.hpp"
#include "game/scene/scene.hpp"
#include "game/species/species.hpp"
#include "game/world/world.hpp"
#include "systems/physics/stem_builder.hpp"
#include "systems/physics/stem_dynamics.hpp"

using namespace ikebana;
namespace physics = ikebana::systems::physics;

namespace {

const glm::dvec3 earth{0.0, 0.0, -9.81};

physics::BuiltStem sunflower_stem(std::uint32_t segments) {
    const auto sp = game::load_species("sunflower");
    physics::StemSpec spec;
    spec.segments = segments;
    spec.length_m = sp->length_m;
    spec.diameter_m = sp->diameter_m;
    spec.youngs_modulus_pa = sp->youngs_modulus_pa;
    spec.second_moment_m4 = sp->second_moment_m4;
    spec.stem_mass_kg = sp->stem_mass_kg;
    spec.head_mass_kg = sp->head_mass_kg;
    spec.stiffness_damping_s = sp->stiffness_damping_s;
    spec.air_drag_per_s = sp->air_drag_per_s;
    spec.direction = glm::normalize(glm::dvec3{1.0, 0.0, 1.0}); // leaning 45 degrees: it bends and sways
    return physics::build_stem(spec);
}

void BM_ArrangementTick(benchmark::State& state) {
    auto scene = game::load_scene(game::asset_dir() / "scenes" / "arrangement.json");
    auto world = game::World::create(*scene);
    if (!world) {
        state.SkipWithError(world.error().message.c_str());
        return;
    }
    sched::DeterministicClock clock((*world)->schedule);
    clock.measure_durations(false);
    clock.run_for_us(1'000'000);
    for (auto _ : state) clock.run_for_us(1000);
}
BENCHMARK(BM_ArrangementTick)->Unit(benchmark::kMicrosecond);

void BM_StemStep(benchmark::State& state) {
    auto stem = sunflower_stem(static_cast<std::uint32_t>(state.range(0)));
    const auto clamp = physics::clamp_bottom(stem);
    physics::StemSolverScratch scratch;
    for (auto _ : state) {
        if (!physics::step_stem(stem.points, stem.rest, stem.springs, &clamp, earth, 0.001, scratch)) state.SkipWithError("step failed");
    }
    state.counters["segments"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_StemStep)->Arg(10)->Arg(20)->Arg(40)->Arg(80)->Unit(benchmark::kMicrosecond);

// Symplectic Euler on the model's own forces: v += h f / m, x += h v; the clamp holds P0.
struct ExplicitChain {
    std::vector<glm::dvec3> force;
    std::vector<physics::StemSegment> segments;
    void step(physics::BuiltStem& s, const components::StemClamp& clamp, double h) {
        physics::stem_forces(s.points, s.rest, s.springs, &clamp, earth, force, segments);
        for (std::size_t p = 1; p < s.points.position_m.size(); ++p) {
            // Rayleigh damping as the implicit step has it: air drag and (here) no stiffness damping,
            // which an explicit chain would pay for with a still smaller step.
            s.points.velocity_m_s[p] += h * (force[p] / s.points.mass_kg[p] - s.springs.air_drag_per_s * s.points.velocity_m_s[p]);
            s.points.position_m[p] += h * s.points.velocity_m_s[p];
        }
    }
};

// The largest explicit step that keeps the leaning stem bounded for 0.2 s (speeds under 10 m/s).
double explicit_limit_s() {
    double stable = 1e-8;
    double unstable = 1e-3;
    while (unstable / stable > 1.02) {
        const double h = std::sqrt(stable * unstable);
        auto s = sunflower_stem(20);
        const auto clamp = physics::clamp_bottom(s);
        ExplicitChain chain;
        bool bounded = true;
        const auto steps = static_cast<long>(0.2 / h);
        for (long i = 0; i < steps && bounded; ++i) {
            chain.step(s, clamp, h);
            if (i % 64 == 0) {
                for (const auto& v : s.points.velocity_m_s) bounded = bounded && std::isfinite(v.x) && glm::length(v) < 10.0;
            }
        }
        (bounded ? stable : unstable) = h;
    }
    return stable;
}

[[gnu::noinline]] void implicit_millisecond(physics::BuiltStem& s, const components::StemClamp& clamp, physics::StemSolverScratch& scratch) {
    (void)physics::step_stem(s.points, s.rest, s.springs, &clamp, earth, 0.001, scratch);
}

[[gnu::noinline]] void explicit_millisecond(physics::BuiltStem& s, const components::StemClamp& clamp, ExplicitChain& chain, long substeps) {
    for (long i = 0; i < substeps; ++i) chain.step(s, clamp, 0.001 / static_cast<double>(substeps));
}

void BM_ChainMillisecondImplicit(benchmark::State& state) {
    auto s = sunflower_stem(20);
    const auto clamp = physics::clamp_bottom(s);
    physics::StemSolverScratch scratch;
    for (auto _ : state) implicit_millisecond(s, clamp, scratch);
    state.counters["steps_per_ms"] = 1;
}
BENCHMARK(BM_ChainMillisecondImplicit)->Unit(benchmark::kMicrosecond);

void BM_ChainMillisecondExplicit(benchmark::State& state) {
    static const double limit = explicit_limit_s();
    const long substeps = static_cast<long>(std::ceil(0.001 / limit));
    auto s = sunflower_stem(20);
    const auto clamp = physics::clamp_bottom(s);
    ExplicitChain chain;
    for (auto _ : state) explicit_millisecond(s, clamp, chain, substeps);
    state.counters["steps_per_ms"] = static_cast<double>(substeps);
    state.counters["limit_us"] = limit * 1e6;
}
BENCHMARK(BM_ChainMillisecondExplicit)->Unit(benchmark::kMicrosecond);

} // namespace

BENCHMARK_MAIN();
