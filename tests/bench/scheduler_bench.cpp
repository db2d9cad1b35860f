// Scheduler overhead per tick: the paper's four rates with empty systems, so what is measured is the
// clock's own work (finding due systems, ordering, command-buffer flush, stats).
#include <benchmark/benchmark.h>

#include "engine/ecs/registry.hpp"
#include "engine/sched/clocks.hpp"

using namespace ikebana;
using namespace ikebana::sched;

static void BM_DeterministicClockPerHapticTick(benchmark::State& state) {
    ecs::Registry reg;
    Schedule s;
    (void)s.add_lane({"sim", &reg, LaneThread::caller, {"p"}});
    const auto systems_per_rate = state.range(0);
    for (const char* rate : {"haptic", "position_estimate", "position_check", "render"}) {
        for (std::int64_t i = 0; i < systems_per_rate; ++i) {
            SystemDesc d;
            d.name = std::string(rate) + std::to_string(i);
            d.lane = "sim";
            d.phase = "p";
            d.rate = rate;
            d.run = [](SystemContext& ctx) { benchmark::DoNotOptimize(ctx.time_us); };
            (void)s.add(d);
        }
    }
    (void)s.finalize();
    DeterministicClock clock(s);
    clock.measure_durations(state.range(1) != 0);
    for (auto _ : state) clock.run_for_us(1000); // one haptic tick (plus the slower systems due in it)
    state.SetItemsProcessed(state.iterations());
    state.SetLabel(state.range(1) ? "with per-system timing" : "timing off");
}
BENCHMARK(BM_DeterministicClockPerHapticTick)->Args({1, 0})->Args({1, 1})->Args({5, 1})->Args({20, 1});

BENCHMARK_MAIN();
