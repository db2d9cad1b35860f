// `ikebana validate`'s analysis at the size the measured-data issue asks for: 10 000 trials, 13
// candidate covariates (12 + insertion count), 1 000 permutations, a planted effect and its
// correlated bystander. The simulation's predictions are computed once outside the timing (18
// distinct conditions, cached); what is timed is everything `analyse_discrepancy` does: tests,
// forward steps, grouped CV of the forms, the backward re-test and 200 bootstrap refits.
// Run: build/release/tests/bench/validation_bench
#include <benchmark/benchmark.h>

#include "../game/analysis/synthetic_trials.hpp"

using namespace ikebana;

namespace {

const game::AnalysisInput& input_of_10k() {
    static const game::AnalysisInput input = [] {
        game::InsertionPredictor predictor;
        test::SyntheticOptions o;
        o.effect = test::PlantedEffect::unknown_numeric;
        o.flowers = 1667;
        o.insertions = 6;
        return test::analysis_input(test::make_synthetic_trials(o, predictor));
    }();
    return input;
}

void BM_AnalyseTenThousandTrials(benchmark::State& state) {
    const auto& input = input_of_10k();
    game::AnalysisOptions options;
    options.permutations = static_cast<std::uint32_t>(state.range(0));
    std::size_t causes = 0;
    for (auto _ : state) {
        auto result = game::analyse_discrepancy(input, options);
        if (!result) state.SkipWithError(result.error().message.c_str());
        else causes = result->causes.size();
        benchmark::DoNotOptimize(causes);
    }
    state.counters["trials"] = static_cast<double>(input.measured_gf.size());
    state.counters["covariates"] = static_cast<double>(input.covariates.columns.size());
    state.counters["causes"] = static_cast<double>(causes);
}
BENCHMARK(BM_AnalyseTenThousandTrials)->Arg(1000)->Unit(benchmark::kSecond)->Iterations(3);

} // namespace

BENCHMARK_MAIN();
