#include "game/analysis/measured_data.hpp"

#include <charconv>
#include <cmath>
#include <set>

namespace ikebana::game {

namespace {
const std::set<std::string> standard = {"flower_id", "insertion", "max_force_gf", "species", "angle_deg", "depth_mm", "pins",
                                        "speed_mm_s", "minutes_since_cut", "hole_reuse", "outcome"};
}

Result<MeasuredData> read_measured_data(assets::CsvTable table, MeasuredForce need) {
    MeasuredData data;
    const std::string& file = table.label;
    for (const char* required : {"flower_id", "insertion", "max_force_gf"}) {
        if (need == MeasuredForce::optional && std::string_view(required) == "max_force_gf") continue;
        if (!table.find(required)) return make_error(ErrorCode::parse_error, file + ": missing the required column '" + std::string(required) + "'");
    }
    auto problem = [&](std::size_t row, const std::string& column, const std::string& what) {
        return make_error(ErrorCode::parse_error, file + ":" + std::to_string(table.line_of_row[row]) + ": column '" + column + "': " + what);
    };
    auto number_in = [&](std::size_t row, const char* column, double lo, double hi, bool integer) -> Result<std::optional<double>> {
        const auto* col = table.find(column);
        if (!col || col->text[row].empty()) return std::optional<double>{};
        // Each cell on its own: one bad cell makes the column text, and must be the one blamed.
        const std::string& cell = col->text[row];
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
        if (ec != std::errc{} || ptr != cell.data() + cell.size() || !std::isfinite(v)) {
            return problem(row, column, "expected a number, got '" + cell + "'");
        }
        if (v < lo || v > hi || (integer && std::floor(v) != v)) {
            return problem(row, column, std::string("expected ") + (integer ? "an integer" : "a number") + " in [" + std::to_string(static_cast<long long>(lo)) +
                                            ", " + std::to_string(static_cast<long long>(hi)) + "], got '" + col->text[row] + "'");
        }
        return std::optional<double>{v};
    };
    data.has_outcome = table.find("outcome") != nullptr;
    for (std::size_t row = 0; row < table.rows(); ++row) {
        MeasuredTrial t;
        t.line = table.line_of_row[row];
        t.flower_id = table.find("flower_id")->text[row];
        if (t.flower_id.empty()) return problem(row, "flower_id", "empty");
        auto insertion = number_in(row, "insertion", 1, 100000, true);
        if (!insertion) return std::move(insertion).error();
        if (!*insertion) return problem(row, "insertion", "empty; expected an integer >= 1");
        t.insertion = static_cast<std::uint32_t>(**insertion);
        // What the physics can mean: no stem takes 100 kgf to push into pins (the paper's are hundreds of gf),
        // no hand pushes faster than 5 m/s, and a cut stem is not kept a year.
        auto force = number_in(row, "max_force_gf", 0, 100000, false);
        if (!force) return std::move(force).error();
        if (*force && **force <= 0.0) return problem(row, "max_force_gf", "expected a positive number");
        if (!*force && need == MeasuredForce::required) return problem(row, "max_force_gf", "expected a positive number");
        t.max_force_gf = force->value_or(0.0);
        if (const auto* s = table.find("species"); s && !s->text[row].empty()) t.species = s->text[row];
        auto angle = number_in(row, "angle_deg", 10, 90, false);
        if (!angle) return std::move(angle).error();
        t.angle_deg = *angle;
        auto depth = number_in(row, "depth_mm", 0, 100, false);
        if (!depth) return std::move(depth).error();
        t.depth_mm = *depth;
        // A stem in the kenzan touches at least one pin; 0 once meant "any" without a word.
        auto pins = number_in(row, "pins", 1, 1000, true);
        if (!pins) return std::move(pins).error();
        if (*pins) t.pins = static_cast<std::uint32_t>(**pins);
        for (const auto& [column, most] : {std::pair{"speed_mm_s", 5000.0}, std::pair{"minutes_since_cut", 525600.0}}) {
            auto v = number_in(row, column, 0, most, false);
            if (!v) return std::move(v).error();
        }
        auto reuse = number_in(row, "hole_reuse", 0, 1, true);
        if (!reuse) return std::move(reuse).error();
        if (const auto* o = table.find("outcome"); o && !o->text[row].empty()) {
            const auto& v = o->text[row];
            if (v != "stood" && v != "fell" && v != "broke") return problem(row, "outcome", "expected stood, fell or broke, got '" + v + "'");
            t.outcome = v;
        }
        data.trials.push_back(std::move(t));
    }
    data.table = std::move(table);
    return data;
}

systems::insertion::Covariates MeasuredData::covariates_of(std::size_t row, const std::set<std::string>* only) const {
    systems::insertion::Covariates c;
    for (const auto& column : table.columns) {
        if (column.name == "flower_id" || column.name == "max_force_gf" || column.name == "outcome" || column.name == "species") continue;
        if (only && !only->contains(column.name)) continue;
        if (column.text[row].empty()) continue;
        if (column.numeric()) c.numeric[column.name] = (*column.numbers)[row];
        else if (!standard.contains(column.name)) c.category[column.name] = column.text[row];
    }
    return c;
}

Result<MeasuredData> load_measured_data(const std::string& path, MeasuredForce force) {
    auto table = assets::load_csv(path);
    if (!table) return std::move(table).error();
    return read_measured_data(std::move(table).value(), force);
}

} // namespace ikebana::game
