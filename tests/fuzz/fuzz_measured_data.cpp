// libFuzzer: the measured-data CSV, through the CSV reader and the measured-data checks, as validate
// reads it (every row measured) and as predict does (a plan: the force may be missing).
#include "engine/assets/csv_table.hpp"
#include "game/analysis/measured_data.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto table = assets::parse_csv(fuzz::text_of(data, size), fuzz::label);
    fuzz::expect_named(table);
    if (table) {
        fuzz::expect_named(game::read_measured_data(*table));
        fuzz::expect_named(game::read_measured_data(std::move(table).value(), game::MeasuredForce::optional));
    }
    return 0;
}
