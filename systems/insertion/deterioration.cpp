#include "systems/insertion/deterioration.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

namespace ikebana::systems::insertion {

std::vector<double> expand_deterioration(const std::string& model, const std::vector<double>& table) {
    if (table.empty()) return {};
    if (model == "paper_baseline") {
        std::vector<double> out(table.begin(), table.begin() + std::min<std::ptrdiff_t>(2, static_cast<std::ptrdiff_t>(table.size())));
        if (table.size() > 2) {
            const auto last = table.begin() + std::min<std::ptrdiff_t>(6, static_cast<std::ptrdiff_t>(table.size()));
            out.push_back(std::accumulate(table.begin() + 2, last, 0.0) / static_cast<double>(last - (table.begin() + 2)));
        }
        return out;
    }
    if (model == "table_hold_last") return table;
    if (model == "none") return {table.front()};
    return {};
}

double term_basis(const std::string& form, double x, double scale) {
    if (form == "constant") return 1.0;
    if (form == "linear") return x;
    if (form == "log") return std::log(std::max(x + scale, 1e-9));
    if (form == "saturating") return scale > 0.0 ? 1.0 - std::exp(-x / scale) : 0.0;
    if (form == "power") return std::pow(std::max(x, 0.0), scale);
    if (form == "step") return x >= scale ? 1.0 : 0.0;
    if (form == "peaked") return scale > 0.0 ? (x / scale) * (x / scale) : 0.0; // x - origin: 0 at the peak (or trough)
    return 0.0;
}

double extension_exponent(const std::vector<components::DeteriorationTerm>& terms, std::uint32_t insertion,
                          const Covariates& covariates) {
    double exponent = 0.0;
    for (const auto& t : terms) {
        if (t.form == "category") {
            const auto it = covariates.category.find(t.covariate);
            if (it != covariates.category.end() && it->second == t.category) exponent += t.coefficient;
            continue;
        }
        // A covariate's value for this insertion: the world's, or (missing_covariates) the centre of
        // the range it was fitted on; nullopt when neither is known.
        auto value_of = [&](const std::string& name, double low, double high) -> std::optional<double> {
            double x = 0.0;
            if (name == "insertion") {
                x = static_cast<double>(insertion);
            } else if (const auto it = covariates.numeric.find(name); it != covariates.numeric.end() && !std::isnan(it->second)) {
                x = it->second; // NaN: kept in the map but absent for this insertion
            } else {
                if (!(high > low)) return std::nullopt;
                x = 0.5 * (low + high);
            }
            return high > low ? std::clamp(x, low, high) : x;
        };
        double x = 0.0;
        if (t.form != "constant") {
            const auto v = value_of(t.covariate, t.range_low, t.range_high);
            if (!v) continue; // no value and no fitted range to take the centre of: the term does not apply
            x = *v;
        }
        double times = 1.0;
        if (!t.times_covariate.empty()) {
            const auto v = value_of(t.times_covariate, t.times_low, t.times_high);
            if (!v) continue;
            times = *v - t.times_origin;
        }
        exponent += t.coefficient * term_basis(t.form, x - t.origin, t.scale) * times;
    }
    return std::isfinite(exponent) ? exponent : 0.0;
}

double extension_factor(const std::vector<components::DeteriorationTerm>& terms, std::uint32_t insertion,
                        const Covariates& covariates) {
    // A hand-edited or wild term must not give the physics an infinite or vanishing resistance:
    // the factor stays within e^-5..e^5 (0.007..148), far outside anything a fit to data gives.
    return std::exp(std::clamp(extension_exponent(terms, insertion, covariates), -5.0, 5.0));
}

bool set_on_every_insertion(const std::string& covariate) {
    return covariate == "insertion" || covariate == "minutes_since_cut" || covariate == "angle_deg" || covariate == "hole_reuse" ||
           covariate == "pins";
}

std::vector<MissingCovariate> missing_covariates(const std::vector<components::DeteriorationTerm>& terms, const Covariates& world) {
    std::vector<MissingCovariate> out;
    auto said = [&](const std::string& name) { return std::any_of(out.begin(), out.end(), [&](const MissingCovariate& m) { return m.name == name; }); };
    // A numeric covariate the term reads (itself, or the one an interaction multiplies by).
    auto numeric = [&](const std::string& name, double low, double high) {
        if (name.empty() || set_on_every_insertion(name) || world.numeric.contains(name) || said(name) || !(high > low)) return;
        out.push_back({name, true, 0.5 * (low + high), low, high});
    };
    for (const auto& t : terms) {
        if (t.form == "constant") continue;
        if (t.form == "category") {
            if (!set_on_every_insertion(t.covariate) && !world.category.contains(t.covariate) && !said(t.covariate)) out.push_back({t.covariate, false, 0.0, 0.0, 0.0});
            continue;
        }
        numeric(t.covariate, t.range_low, t.range_high);
        numeric(t.times_covariate, t.times_low, t.times_high);
    }
    return out;
}

double soft_resistance_n_per_m(const components::PinResistance& model, std::uint32_t insertion, const Covariates& covariates, bool extended) {
    if (model.n_per_m_by_insertion.empty()) return 0.0;
    const std::size_t k = std::clamp<std::size_t>(insertion, 1, model.n_per_m_by_insertion.size()) - 1;
    return model.n_per_m_by_insertion[k] * (extended ? extension_factor(model.extension, insertion, covariates) : 1.0);
}

} // namespace ikebana::systems::insertion
