// libFuzzer: the measured-data CSV, through the CSV reader and the measured-data checks, as validate
// reads it (every row measured) and as predict does (a plan: the force may be missing).
#include "engine/assets/csv_table.hpp"
#include "engine/core/utf8.hpp"
#include "game/analysis/measured_data.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto table = assets::parse_csv(fuzz::text_of(data, size), fuzz::label);
    fuzz::expect_named(table);
    if (table) {
        // Whatever bytes came in, the cells go out as UTF-8 (a file that is not is read as Windows-1252).
        for (const auto& column : table->columns) {
            if (!is_utf8(column.name)) std::abort();
            for (const auto& cell : column.text) {
                if (!is_utf8(cell)) std::abort();
            }
        }
        fuzz::expect_named(game::read_measured_data(*table));
        fuzz::expect_named(game::read_measured_data(std::move(table).value(), game::MeasuredForce::optional));
    }
    return 0;
}
