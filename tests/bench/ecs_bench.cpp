// ECS benchmarks: iteration over 1k-1M entities, structural changes, and the storage comparison that
// chose sparse sets (docs/ecs.md). Run: build/release/tests/bench/ecs_bench
#include <benchmark/benchmark.h>

#include <random>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "engine/ecs/registry.hpp"

using namespace ikebana::ecs;

namespace {
struct Position {
    glm::dvec3 value{};
};
struct Velocity {
    glm::dvec3 value{};
};
struct Mass {
    double kg = 1.0;
};

// Every entity has Position and Velocity; every `mass_every`-th also has Mass.
void fill(Registry& r, std::int64_t n, int mass_every) {
    for (std::int64_t i = 0; i < n; ++i) {
        const Entity e = r.create();
        r.emplace<Position>(e, glm::dvec3{static_cast<double>(i), 0, 0});
        r.emplace<Velocity>(e, glm::dvec3{1, 0, 0});
        if (i % mass_every == 0) r.emplace<Mass>(e, 2.0);
    }
}
} // namespace

static void BM_ViewOneComponent(benchmark::State& state) {
    Registry r;
    fill(r, state.range(0), 1);
    for (auto _ : state) {
        r.view<Position>().each([](Entity, Position& p) { p.value.x += 1.0; });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_ViewOneComponent)->RangeMultiplier(10)->Range(1'000, 1'000'000);

static void BM_ViewTwoComponents(benchmark::State& state) {
    Registry r;
    fill(r, state.range(0), 1);
    for (auto _ : state) {
        r.view<Position, Velocity>().each([](Entity, Position& p, Velocity& v) { p.value += v.value * 0.001; });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_ViewTwoComponents)->RangeMultiplier(10)->Range(1'000, 1'000'000);

// Sparse sets shine here: the view walks the small Mass set, not the million positions.
static void BM_ViewSparseThirdComponent(benchmark::State& state) {
    Registry r;
    fill(r, state.range(0), 100);
    for (auto _ : state) {
        r.view<Position, Velocity, Mass>().each([](Entity, Position& p, Velocity& v, Mass& m) { p.value += v.value * m.kg; });
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * state.range(0) / 100);
}
BENCHMARK(BM_ViewSparseThirdComponent)->RangeMultiplier(10)->Range(1'000, 1'000'000);

// Reference points for the storage choice ----------------------------------------------------------
// Archetype best case: both components in parallel arrays, no membership tests at all.
static void BM_Reference_ArchetypeArrays(benchmark::State& state) {
    const auto n = static_cast<std::size_t>(state.range(0));
    std::vector<Position> pos(n);
    std::vector<Velocity> vel(n, Velocity{glm::dvec3{1, 0, 0}});
    for (auto _ : state) {
        for (std::size_t i = 0; i < n; ++i) pos[i].value += vel[i].value * 0.001;
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_Reference_ArchetypeArrays)->RangeMultiplier(10)->Range(1'000, 1'000'000);

// Naive: a hash map per component type.
static void BM_Reference_HashMaps(benchmark::State& state) {
    const auto n = static_cast<std::uint64_t>(state.range(0));
    std::unordered_map<std::uint64_t, Position> pos;
    std::unordered_map<std::uint64_t, Velocity> vel;
    for (std::uint64_t i = 0; i < n; ++i) {
        pos[i] = Position{};
        vel[i] = Velocity{glm::dvec3{1, 0, 0}};
    }
    for (auto _ : state) {
        for (auto& [id, p] : pos) p.value += vel.find(id)->second.value * 0.001;
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_Reference_HashMaps)->RangeMultiplier(10)->Range(1'000, 1'000'000);

// Structural changes ----------------------------------------------------------------------------------
static void BM_CreateEmplaceDestroy(benchmark::State& state) {
    Registry r;
    std::vector<Entity> entities(static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) {
        for (auto& e : entities) {
            e = r.create();
            r.emplace<Position>(e);
            r.emplace<Velocity>(e);
        }
        for (const auto e : entities) r.destroy(e);
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_CreateEmplaceDestroy)->Arg(1'000)->Arg(100'000);

// Add and remove a component through the command buffer, as a system does mid-iteration.
static void BM_DeferredAddRemove(benchmark::State& state) {
    Registry r;
    fill(r, state.range(0), 1);
    for (auto _ : state) {
        r.view<Position>().each([&](Entity e, Position&) { r.commands().emplace<Mass>(e, 1.0); });
        r.commands().apply();
        r.view<Mass>().each([&](Entity e, Mass&) { r.commands().remove<Mass>(e); });
        r.commands().apply();
    }
    state.SetItemsProcessed(state.iterations() * state.range(0) * 2);
}
BENCHMARK(BM_DeferredAddRemove)->Arg(1'000)->Arg(100'000);

static void BM_StateHash(benchmark::State& state) {
    Registry r;
    fill(r, state.range(0), 10);
    for (auto _ : state) benchmark::DoNotOptimize(r.state_hash());
    state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_StateHash)->Arg(1'000)->Arg(100'000);

BENCHMARK_MAIN();
