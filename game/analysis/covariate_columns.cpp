#include "game/analysis/covariate_columns.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace ikebana::game {

Result<CovariateSet> candidate_covariates(const assets::CsvTable& table, const std::vector<std::string>& ignore) {
    for (const auto& name : ignore) {
        if (!table.find(name)) return make_error(ErrorCode::invalid_argument, table.label + ": no column '" + name + "' to ignore");
    }
    CovariateSet out;
    const std::size_t n = table.rows();
    for (const auto& column : table.columns) {
        if (column.name == "flower_id" || column.name == "max_force_gf" || column.name == "outcome" ||
            column.name.starts_with("predicted_") || std::find(ignore.begin(), ignore.end(), column.name) != ignore.end()) {
            continue;
        }
        CovariateColumn c;
        c.name = column.name;
        c.numeric = column.numeric();
        if (c.numeric) {
            std::vector<double> present;
            for (double v : *column.numbers) {
                if (std::isfinite(v)) present.push_back(v);
            }
            if (present.empty()) continue;
            // The middle of the present values' range: what the species model takes for a covariate it
            // is not given (the centre of the fitted range), so a blank row is fitted as it is predicted.
            const auto [least, most] = std::minmax_element(present.begin(), present.end());
            const double middle = 0.5 * (*least + *most);
            c.fill_value = middle;
            c.values.reserve(n);
            for (double v : *column.numbers) {
                c.missing += std::isfinite(v) ? 0 : 1;
                c.values.push_back(std::isfinite(v) ? v : middle);
            }
            const auto [lo, hi] = std::minmax_element(c.values.begin(), c.values.end());
            if (*lo == *hi) {
                out.constant.push_back(c.name);
                continue;
            }
        } else {
            std::map<std::string, std::size_t> counts;
            for (const auto& cell : column.text) ++counts[cell.empty() ? "(missing)" : cell];
            if (counts.size() < 2) {
                out.constant.push_back(c.name);
                continue;
            }
            for (const auto& [name, count] : counts) c.levels.push_back(name);
            // Most common first, ties by name: the reference level the others are compared with.
            std::stable_sort(c.levels.begin(), c.levels.end(), [&](const auto& a, const auto& b) { return counts[a] > counts[b]; });
            std::map<std::string, std::uint32_t> index;
            for (std::uint32_t i = 0; i < c.levels.size(); ++i) index[c.levels[i]] = i;
            c.level.reserve(n);
            for (const auto& cell : column.text) {
                c.missing += cell.empty() ? 1 : 0;
                c.level.push_back(index[cell.empty() ? "(missing)" : cell]);
            }
        }
        out.columns.push_back(std::move(c));
    }
    return out;
}

} // namespace ikebana::game
