#include "synthetic_trials.hpp"

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <stdexcept>

#include "game/species/species.hpp"

namespace ikebana::test {

PlantedTruth truth_of(PlantedEffect effect) {
    switch (effect) {
    case PlantedEffect::none: return {"", ""};
    case PlantedEffect::unknown_numeric: return {"humidity_pct", "increases"};
    case PlantedEffect::category: return {"vase", "decreases"};
    case PlantedEffect::station: return {"station", "decreases"};
    case PlantedEffect::insertion_count: return {"insertion", "decreases"};
    case PlantedEffect::step_threshold: return {"storage_days", "decreases"};
    case PlantedEffect::saturating_decay: return {"soak_minutes", "decreases"};
    case PlantedEffect::peaked_optimum: return {"humidity_pct", "nonmonotone"};
    case PlantedEffect::gross_outliers: return {"humidity_pct", "increases"};
    case PlantedEffect::two_effects: return {"humidity_pct", "increases"}; // and storage_days, decreases
    case PlantedEffect::interaction: return {"humidity_pct", "increases"}; // more so the longer stored
    }
    return {"", ""};
}

const char* name_of(PlantedEffect effect) {
    switch (effect) {
    case PlantedEffect::none: return "none";
    case PlantedEffect::unknown_numeric: return "unknown_numeric";
    case PlantedEffect::category: return "category";
    case PlantedEffect::station: return "station";
    case PlantedEffect::insertion_count: return "insertion_count";
    case PlantedEffect::step_threshold: return "step_threshold";
    case PlantedEffect::saturating_decay: return "saturating_decay";
    case PlantedEffect::peaked_optimum: return "peaked_optimum";
    case PlantedEffect::gross_outliers: return "gross_outliers";
    case PlantedEffect::two_effects: return "two_effects";
    case PlantedEffect::interaction: return "interaction";
    }
    return "?";
}

SyntheticData make_synthetic_trials(const SyntheticOptions& o, game::InsertionPredictor& predictor) {
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::mt19937_64 gross_rng(o.seed ^ 0x6055);
    std::uniform_real_distribution<double> slips(0.0, 1.0);
    std::normal_distribution<double> slips_normal(0.0, 1.0);
    const char* vases[] = {"glass", "ceramic", "metal"};
    const char* suppliers[] = {"north", "south", "east"};
    SyntheticData out;
    out.truth = truth_of(o.effect);
    std::ostringstream csv;
    csv << "# synthetic trials, planted effect: " << name_of(o.effect) << ", seed " << o.seed << "\n";
    csv << "flower_id,insertion,max_force_gf,species,angle_deg,speed_mm_s,minutes_since_cut,hole_reuse,humidity_pct,dew_point,"
           "storage_days,soak_minutes,vase,supplier,bench,stem_mark";
    for (std::uint32_t k = 0; k < o.extra_covariates; ++k) csv << ",noise_" << k;
    if (o.station_column || o.effect == PlantedEffect::station) csv << ",station";
    if (o.wide_levels > 0) csv << ",batch";
    for (std::uint32_t k = 0; k < o.near_copies; ++k) csv << ",humidity_copy_" << k + 1;
    csv << "\n";
    std::size_t row_number = 0;
    for (std::uint32_t f = 0; f < o.flowers; ++f) {
        // Per flower: its conditions, and the bystanders correlated with the planted causes.
        const double angle = 30.0 + 15.0 * static_cast<double>(rng() % 3);
        const double humidity = 40.0 + 40.0 * uniform(rng);
        const double dew_point = 0.35 * humidity + 3.0 * normal(rng);
        const auto storage = static_cast<double>(rng() % 11);
        const double soak = 90.0 * uniform(rng);
        const auto vase = static_cast<std::size_t>(rng() % 3);
        const std::size_t supplier = uniform(rng) < 0.75 ? vase : static_cast<std::size_t>(rng() % 3);
        const double cut_start = 5.0 + 55.0 * uniform(rng);
        const double flower_noise = o.flower_noise_sd * normal(rng);
        for (std::uint32_t k = 1; k <= o.insertions; ++k) {
            const double minutes = cut_start + 3.0 * (k - 1) + uniform(rng);
            const double speed = 20.0 + 40.0 * uniform(rng);
            const int reuse = k > 1 && uniform(rng) < 0.3 ? 1 : 0;
            const char* bench = uniform(rng) < 0.5 ? "left" : "right";
            const double mark = normal(rng);
            double effect = 0.0;
            switch (o.effect) {
            case PlantedEffect::none: break;
            case PlantedEffect::unknown_numeric: effect = 0.006 * (humidity - 60.0); break;
            case PlantedEffect::category: effect = vase == 2 ? -0.2 : 0.0; break;
            case PlantedEffect::insertion_count: effect = -0.05 * (k - 1.0); break;
            case PlantedEffect::step_threshold: effect = storage >= 6.0 ? -0.2 : 0.0; break;
            case PlantedEffect::saturating_decay: effect = -0.25 * (1.0 - std::exp(-soak / 20.0)); break;
            case PlantedEffect::station: effect = f % 12 == 6 ? -0.15 : 0.0; break;
            // Stems resist most at 60 % humidity and 15 % less at 40 and 80 %.
            case PlantedEffect::peaked_optimum: effect = -0.15 * ((humidity - 60.0) / 20.0) * ((humidity - 60.0) / 20.0); break;
            case PlantedEffect::gross_outliers: effect = 0.004 * (humidity - 60.0); break;
            case PlantedEffect::two_effects: effect = 0.004 * (humidity - 60.0) + (storage >= 6.0 ? -0.15 : 0.0); break;
            case PlantedEffect::interaction: effect = 0.006 * (humidity - 60.0) * storage / 5.0; break;
            }
            game::InsertionConditions c;
            c.species = "sunflower";
            c.angle_deg = angle;
            c.insertion = k;
            const auto p = predictor.predict(c);
            if (!p) throw std::runtime_error(p.error().message);
            const double simulated = p->max_force_n / game::gram_force_n;
            effect *= o.effect_scale;
            double measured = simulated * std::exp(effect + flower_noise + o.trial_noise_sd * normal(rng));
            if (o.effect == PlantedEffect::gross_outliers && slips(gross_rng) < 0.03) { // its own stream: the other draws stay
                measured *= slips(gross_rng) < 0.5 ? 0.35 : 2.5;
                out.gross_rows.push_back(row_number);
            }
            out.simulated_gf.push_back(simulated);
            out.true_log_factor.push_back(effect);
            char row[512];
            std::snprintf(row, sizeof row, "F%03u,%u,%.3f,sunflower,%.0f,%.2f,%.2f,%d,%.2f,%.2f,%.0f,%.2f,%s,%s,%s,%.4f", f + 1, k, measured,
                          angle, speed, minutes, reuse, humidity, dew_point, storage, soak, vases[vase], suppliers[supplier], bench, mark);
            csv << row;
            for (std::uint32_t e = 0; e < o.extra_covariates; ++e) csv << ',' << normal(rng);
            if (o.station_column || o.effect == PlantedEffect::station) csv << ",S" << (f % 12 < 9 ? "0" : "") << f % 12 + 1;
            if (o.wide_levels > 0) csv << ",LOT" << row_number / std::max<std::uint32_t>(1, o.rows_per_lot) % o.wide_levels;
            ++row_number;
            for (std::uint32_t copy = 0; copy < o.near_copies; ++copy) csv << ',' << humidity + 0.5 * slips_normal(gross_rng);
            csv << "\n";
        }
    }
    out.csv = csv.str();
    auto table = assets::parse_csv(out.csv, "synthetic.csv");
    if (!table) throw std::runtime_error(table.error().message);
    auto data = game::read_measured_data(std::move(table).value());
    if (!data) throw std::runtime_error(data.error().message);
    out.data = std::move(data).value();
    return out;
}

game::AnalysisInput analysis_input(const SyntheticData& d) {
    game::AnalysisInput in;
    for (std::size_t i = 0; i < d.data.trials.size(); ++i) {
        in.flower.push_back(d.data.trials[i].flower_id);
        in.measured_gf.push_back(d.data.trials[i].max_force_gf);
        in.predicted_gf.push_back(d.simulated_gf[i]);
    }
    auto covariates = game::candidate_covariates(d.data.table, {});
    if (!covariates) throw std::runtime_error(covariates.error().message);
    in.covariates = std::move(covariates).value();
    return in;
}

} // namespace ikebana::test
