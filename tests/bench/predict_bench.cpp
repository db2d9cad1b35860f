// Issue 16's file: 10,000 insertions of 2,000 flowers (five each) with a continuous depth, a push
// speed, four angles, a numeric and a categorical column the model does not know. Timed: `ikebana
// predict` (every row through the simulation, written back with its prediction) and `ikebana validate`
// end to end on the same file. Depths are 8-13 mm: the standard kenzan's pins are 13 mm tall, and a
// deeper row is refused (the stem would be pushed into the base plate).
// Run: build/release/tests/bench/predict_bench
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>

#include "engine/assets/files.hpp"
#include "game/analysis/validation.hpp"
#include "game/cli/predict_command.hpp"

using namespace ikebana;

namespace {

std::filesystem::path lab_file() {
    static const std::filesystem::path path = [] {
        const auto p = std::filesystem::temp_directory_path() / "ikebana_predict_10000.csv";
        std::mt19937_64 rng(16);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        std::normal_distribution<double> noise(0.0, 0.08);
        const double angles[4] = {30.0, 45.0, 60.0, 90.0};
        const char* cultivars[3] = {"tall", "dwarf", "teddy"};
        std::ostringstream csv;
        csv << "flower_id,insertion,max_force_gf,angle_deg,depth_mm,speed_mm_s,humidity_pct,cultivar\n";
        const double table[5] = {480, 380, 330, 300, 280}; // Table 2's levels by insertion, roughly
        for (int f = 0; f < 2000; ++f) {
            const double humidity = 40.0 + 40.0 * unit(rng);
            const char* cultivar = cultivars[f % 3];
            for (int k = 1; k <= 5; ++k) {
                const double depth = 8.0 + 5.0 * unit(rng);
                char row[160];
                std::snprintf(row, sizeof row, "F%04d,%d,%.1f,%.0f,%.2f,%.1f,%.1f,%s\n", f, k, table[k - 1] * depth / 13.0 * std::exp(noise(rng)),
                              angles[(f + k) % 4], depth, 20.0 + 60.0 * unit(rng), humidity, cultivar);
                csv << row;
            }
        }
        (void)assets::write_text_file(p, csv.str());
        return p;
    }();
    return path;
}

void BM_PredictTenThousandRowsOfContinuousDepth(benchmark::State& state) {
    const auto file = lab_file();
    const auto out = std::filesystem::temp_directory_path() / "ikebana_predict_10000_out.csv";
    for (auto _ : state) {
        if (game::run_predict(file.string(), "", out.string()) != 0) {
            state.SkipWithError("predict failed");
            break;
        }
    }
    state.counters["rows"] = 10000;
}
BENCHMARK(BM_PredictTenThousandRowsOfContinuousDepth)->Unit(benchmark::kSecond)->Iterations(1);

void BM_ValidateTenThousandRowsOfContinuousDepth(benchmark::State& state) {
    const auto file = lab_file();
    game::ValidationOptions options;
    options.species_override = "sunflower";
    for (auto _ : state) {
        auto result = game::run_validation(file.string(), options);
        if (!result) {
            state.SkipWithError(result.error().message.c_str());
            break;
        }
        benchmark::DoNotOptimize(result->analysis.causes.size());
    }
    state.counters["rows"] = 10000;
}
BENCHMARK(BM_ValidateTenThousandRowsOfContinuousDepth)->Unit(benchmark::kSecond)->Iterations(1);

} // namespace

BENCHMARK_MAIN();
