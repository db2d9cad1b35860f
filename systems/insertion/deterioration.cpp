#include "systems/insertion/deterioration.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

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

double extension_factor(const std::vector<components::DeteriorationTerm>& terms, std::uint32_t insertion,
                        const Covariates& covariates) {
    double exponent = 0.0;
    for (const auto& t : terms) {
        if (t.form == "category") {
            const auto it = covariates.category.find(t.covariate);
            if (it != covariates.category.end() && it->second == t.category) exponent += t.coefficient;
            continue;
        }
        double x = 0.0;
        if (t.covariate == "insertion") {
            x = static_cast<double>(insertion);
        } else if (const auto it = covariates.numeric.find(t.covariate); it != covariates.numeric.end()) {
            x = it->second;
        } else if (t.form != "constant") {
            if (!(t.range_high > t.range_low)) continue; // no fitted range to take the centre of: the term does not apply
            x = 0.5 * (t.range_low + t.range_high);     // a covariate this world does not have (missing_covariates)
        }
        if (t.range_high > t.range_low) x = std::clamp(x, t.range_low, t.range_high);
        exponent += t.coefficient * term_basis(t.form, x - t.origin, t.scale);
    }
    // A hand-edited or wild term must not give the physics an infinite or vanishing resistance:
    // the factor stays within e^-5..e^5 (0.007..148), far outside anything a fit to data gives.
    if (!std::isfinite(exponent)) exponent = 0.0;
    return std::exp(std::clamp(exponent, -5.0, 5.0));
}

bool set_on_every_insertion(const std::string& covariate) {
    return covariate == "insertion" || covariate == "minutes_since_cut" || covariate == "angle_deg" || covariate == "hole_reuse" ||
           covariate == "pins";
}

std::vector<MissingCovariate> missing_covariates(const std::vector<components::DeteriorationTerm>& terms, const Covariates& world) {
    std::vector<MissingCovariate> out;
    for (const auto& t : terms) {
        if (t.form == "constant" || set_on_every_insertion(t.covariate)) continue;
        if (std::any_of(out.begin(), out.end(), [&](const MissingCovariate& m) { return m.name == t.covariate; })) continue;
        if (t.form == "category") {
            if (!world.category.contains(t.covariate)) out.push_back({t.covariate, false, 0.0, 0.0, 0.0});
            continue;
        }
        if (world.numeric.contains(t.covariate) || !(t.range_high > t.range_low)) continue;
        out.push_back({t.covariate, true, 0.5 * (t.range_low + t.range_high), t.range_low, t.range_high});
    }
    return out;
}

double soft_resistance_n_per_m(const components::PinResistance& model, std::uint32_t insertion, const Covariates& covariates) {
    if (model.n_per_m_by_insertion.empty()) return 0.0;
    const std::size_t k = std::clamp<std::size_t>(insertion, 1, model.n_per_m_by_insertion.size()) - 1;
    return model.n_per_m_by_insertion[k] * extension_factor(model.extension, insertion, covariates);
}

} // namespace ikebana::systems::insertion
