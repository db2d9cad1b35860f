#include "game/analysis/validation.hpp"

#include <cstdio>
#include <cmath>
#include <limits>
#include <cctype>
#include <filesystem>
#include <map>
#include <set>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/analysis/cause_explanations.hpp"
#include "game/species/species.hpp"

namespace ikebana::game {

std::optional<FlowerSpread> flower_spread(const std::vector<std::string>& flower, const std::vector<double>& residual_log) {
    std::map<std::string, std::pair<double, std::size_t>> by_flower; // sum, rows
    for (std::size_t i = 0; i < flower.size() && i < residual_log.size(); ++i) {
        auto& [sum, n] = by_flower[flower[i]];
        sum += residual_log[i];
        ++n;
    }
    std::size_t groups = 0, rows = 0;
    double n_squared = 0.0, grand = 0.0;
    for (const auto& [id, g] : by_flower) {
        if (g.second < 2) continue; // a flower of one row says nothing of its own scatter
        ++groups;
        rows += g.second;
        n_squared += static_cast<double>(g.second) * static_cast<double>(g.second);
        grand += g.first;
    }
    if (groups < 3) return std::nullopt;
    grand /= static_cast<double>(rows);
    double within = 0.0, between = 0.0;
    for (std::size_t i = 0; i < flower.size() && i < residual_log.size(); ++i) {
        const auto& g = by_flower[flower[i]];
        if (g.second < 2) continue;
        const double mean = g.first / static_cast<double>(g.second);
        within += (residual_log[i] - mean) * (residual_log[i] - mean);
    }
    for (const auto& [id, g] : by_flower) {
        if (g.second < 2) continue;
        const double mean = g.first / static_cast<double>(g.second);
        between += static_cast<double>(g.second) * (mean - grand) * (mean - grand);
    }
    const double ms_within = within / static_cast<double>(rows - groups);
    const double ms_between = between / static_cast<double>(groups - 1);
    // Rows a flower on average, corrected for unequal counts.
    const double n0 = (static_cast<double>(rows) - n_squared / static_cast<double>(rows)) / static_cast<double>(groups - 1);
    FlowerSpread out;
    out.sd_log = std::sqrt(std::max(0.0, (ms_between - ms_within) / n0));
    out.within_sd_log = std::sqrt(ms_within);
    out.flowers = groups;
    out.rows = rows;
    return out;
}

std::vector<CalibrationBin> calibration_bins(const MeasuredData& data, const std::vector<double>& fall_probability) {
    const double edges[] = {0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0};
    std::vector<CalibrationBin> bins(6);
    for (std::size_t b = 0; b < bins.size(); ++b) {
        bins[b].low = edges[b];
        bins[b].high = edges[b + 1];
    }
    for (std::size_t i = 0; i < data.trials.size() && i < fall_probability.size(); ++i) {
        const auto& o = data.trials[i].outcome;
        if (!o || (*o != "stood" && *o != "fell")) continue;
        const double p = std::clamp(fall_probability[i], 0.0, 1.0);
        std::size_t b = 0;
        while (b + 1 < bins.size() && p >= bins[b].high) ++b;
        ++bins[b].rows;
        bins[b].predicted += p;
        bins[b].fell += *o == "fell" ? 1.0 : 0.0;
    }
    std::erase_if(bins, [](const CalibrationBin& b) { return b.rows == 0; });
    for (auto& b : bins) {
        const auto n = static_cast<double>(b.rows);
        b.predicted /= n;
        b.fell /= n;
        b.se = std::sqrt(b.fell * (1.0 - b.fell) / n);
    }
    return bins;
}

std::optional<OutcomeScores> score_outcomes(const MeasuredData& data, const std::vector<double>& fall_probability) {
    OutcomeScores s;
    std::size_t right = 0;
    for (std::size_t i = 0; i < data.trials.size() && i < fall_probability.size(); ++i) {
        const auto& o = data.trials[i].outcome;
        if (!o || (*o != "stood" && *o != "fell")) continue;
        const double fell = *o == "fell" ? 1.0 : 0.0;
        const double p = std::clamp(fall_probability[i], 0.0, 1.0);
        ++s.rows;
        right += ((p > 0.5) == (fell == 1.0)) ? 1 : 0;
        s.brier += (p - fell) * (p - fell);
        // A chance of exactly 0 or 1 (every placement of the mixture alike) would make one wrong row cost
        // without bound: kept within [0.001, 0.999].
        const double given = std::clamp(fell == 1.0 ? p : 1.0 - p, 0.001, 0.999);
        s.log_loss -= std::log(given);
    }
    if (s.rows == 0) return std::nullopt;
    const auto n = static_cast<double>(s.rows);
    s.accuracy = static_cast<double>(right) / n;
    s.brier /= n;
    s.log_loss /= n;
    return s;
}

namespace {

// The clipped log-loss of one row (score_outcomes' rule); a chance nobody simulated (NaN, chance_at
// beyond its curve) costs the most a row can.
double row_log_loss(double chance, bool fell) {
    if (!std::isfinite(chance)) return -std::log(0.001);
    return -std::log(std::clamp(fell ? chance : 1.0 - chance, 0.001, 0.999));
}

nlohmann::json species_term_json(const components::DeteriorationTerm& t) {
    nlohmann::json j = {{"covariate", t.covariate}, {"form", t.form}, {"coefficient", t.coefficient}};
    if (t.form != "constant" && t.form != "category" && t.form != "linear") j["scale"] = t.scale;
    if (t.origin != 0.0) j["origin"] = t.origin;
    if (t.range_high > t.range_low) j["range"] = {t.range_low, t.range_high};
    if (t.form == "category") j["category"] = t.category;
    if (!t.times_covariate.empty()) {
        j["times"] = {{"covariate", t.times_covariate}, {"origin", t.times_origin}};
        j["times"]["range"] = {t.times_low, t.times_high}; // the reader needs it, equal ends or not
    }
    return j;
}

} // namespace

double chance_at(const HoldCurve& curve, double log_factor) {
    const auto& x = curve.log_factor;
    if (x.empty()) return 0.0;
    // Beyond the simulated factors by more than half their end gaps the chance is unknown, not the end's:
    // a fit that took the end's for it held the stems at 0.3 where the curve said 0.5 (the species,
    // run, fell everywhere: log-loss 0.36 promised, 1.15 given).
    if (x.size() >= 2) {
        const double below = x.front() - 0.5 * (x[1] - x.front()), above = x.back() + 0.5 * (x.back() - x[x.size() - 2]);
        if (log_factor < below || log_factor > above) return std::numeric_limits<double>::quiet_NaN();
    }
    std::size_t nearest = 0;
    for (std::size_t j = 1; j < x.size(); ++j) {
        if (std::abs(x[j] - log_factor) < std::abs(x[nearest] - log_factor)) nearest = j;
    }
    return curve.chance[nearest];
}

std::vector<components::DeteriorationTerm> fit_hold_terms(const MeasuredData& data, const std::vector<std::size_t>& rows,
                                                          const std::vector<components::DeteriorationTerm>& terms,
                                                          const std::vector<HoldCurve>& curves, double* log_loss) {
    const std::size_t n = rows.size(), k_count = terms.size();
    // Each term's basis at each row: the term alone at coefficient 1, as the insertion system reads it.
    std::vector<std::vector<double>> basis(k_count, std::vector<double>(n));
    std::vector<double> span(k_count, 0.0);
    for (std::size_t k = 0; k < k_count; ++k) {
        auto unit = terms[k];
        unit.coefficient = 1.0;
        double lo = INFINITY, hi = -INFINITY;
        for (std::size_t i = 0; i < n; ++i) {
            const auto& t = data.trials[rows[i]];
            basis[k][i] = systems::insertion::extension_exponent({unit}, t.insertion, data.covariates_of(rows[i]));
            lo = std::min(lo, basis[k][i]);
            hi = std::max(hi, basis[k][i]);
        }
        span[k] = hi - lo > 1e-12 ? hi - lo : std::max(std::abs(hi), 1.0); // a level: its value
    }
    std::vector<double> eta(n, 0.0), beta(k_count, 0.0);
    const auto loss_with = [&](std::size_t k, double value) {
        double s = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const double e = eta[i] + (value - beta[k]) * basis[k][i];
            s += row_log_loss(chance_at(curves[i], e), *data.trials[rows[i]].outcome == "fell");
        }
        return s / static_cast<double>(std::max<std::size_t>(n, 1));
    };
    // The chance is nearly a step function of each coefficient (placements stand or fall): a grid, not a
    // gradient. A term moves the holding by at most a factor e^1.5 (4.5) across its column; a row
    // pushed beyond the simulated factors (0.5 to 2) costs the worst loss, so the fit stays within them.
    constexpr int steps = 60;
    // A start along the correction itself: what makes a row fall more holds it less, so the terms begin
    // at -c times the correction's own coefficients (c chosen on a grid, with a level), and coordinate
    // descent goes on from there. From zero, one coefficient at a time, the level took what it could
    // and the columns' terms were left at nothing: a step function has no slope to follow.
    std::vector<double> correction(n, 0.0);
    std::size_t level = k_count;
    for (std::size_t k = 0; k < k_count; ++k) {
        if (terms[k].form == "constant") {
            level = k;
            continue;
        }
        for (std::size_t i = 0; i < n; ++i) correction[i] += terms[k].coefficient * basis[k][i];
    }
    const auto start_loss = [&](double c, double shift) {
        double s = 0.0;
        for (std::size_t i = 0; i < n; ++i) s += row_log_loss(chance_at(curves[i], shift - c * correction[i]), *data.trials[rows[i]].outcome == "fell");
        return s / static_cast<double>(std::max<std::size_t>(n, 1));
    };
    double best = start_loss(0.0, 0.0), best_c = 0.0, best_shift = 0.0;
    for (int a = 0; a <= 40; ++a) {
        const double c = 0.1 * a; // the chance's scale against ln of the holding: 0 to 4
        for (int b = -14; b <= 14; ++b) {
            if (level == k_count && b != 0) continue; // no level term to carry a shift
            const double shift = 0.05 * b;
            const double l = start_loss(c, shift);
            if (l < best - 1e-12) best = l, best_c = c, best_shift = shift;
        }
    }
    for (std::size_t k = 0; k < k_count; ++k) {
        beta[k] = k == level ? best_shift / (basis[k].empty() || basis[k][0] == 0.0 ? 1.0 : basis[k][0]) : -best_c * terms[k].coefficient;
        for (std::size_t i = 0; i < n; ++i) eta[i] += beta[k] * basis[k][i];
    }
    best = k_count ? loss_with(0, beta[0]) : 0.0;
    for (int sweep = 0; sweep < 4; ++sweep) {
        for (std::size_t k = 0; k < k_count; ++k) {
            double chosen = beta[k];
            for (int j = -steps; j <= steps; ++j) {
                const double value = 1.5 * j / steps / span[k];
                const double l = loss_with(k, value);
                if (l < best - 1e-12 || (std::abs(l - best) <= 1e-12 && std::abs(value) < std::abs(chosen))) {
                    best = l;
                    chosen = value;
                }
            }
            for (std::size_t i = 0; i < n; ++i) eta[i] += (chosen - beta[k]) * basis[k][i];
            beta[k] = chosen;
        }
    }
    if (log_loss) *log_loss = best;
    std::vector<components::DeteriorationTerm> out;
    for (std::size_t k = 0; k < k_count; ++k) {
        if (beta[k] == 0.0) continue;
        auto t = terms[k];
        t.coefficient = beta[k];
        out.push_back(t);
    }
    return out;
}

Result<std::string> with_hold_terms(const std::string& species_json, const std::vector<components::DeteriorationTerm>& terms) {
    auto j = nlohmann::ordered_json::parse(species_json, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("deterioration")) return make_error(ErrorCode::parse_error, "the extended species is not a species");
    auto& out = j["deterioration"]["terms"];
    if (!out.is_array()) out = nlohmann::ordered_json::array();
    for (const auto& t : terms) {
        nlohmann::ordered_json term = nlohmann::ordered_json::parse(species_term_json(t).dump());
        term["applies_to"] = "hold";
        out.push_back(term);
    }
    std::string json = assets::json_text(j, 2) + "\n";
    if (auto check = parse_species(json, "extended species"); !check) return make_error(ErrorCode::parse_error, "the extended species does not load: " + check.error().message);
    return json;
}

std::optional<OutcomeSearch> search_outcomes(const MeasuredData& data, const AnalysisInput& forces, const std::vector<double>& fall_probability,
                                             const AnalysisOptions& options, std::string& note) {
    OutcomeSearch s;
    std::size_t falls = 0;
    for (std::size_t i = 0; i < data.trials.size() && i < fall_probability.size(); ++i) {
        const auto& o = data.trials[i].outcome;
        if (!o || (*o != "stood" && *o != "fell")) continue;
        s.rows.push_back(i);
        falls += *o == "fell" ? 1 : 0;
    }
    // Below this a permutation test of falls has nothing to permute: every row alike, or too few.
    constexpr std::size_t least_rows = 20, least_each = 5;
    if (s.rows.size() < least_rows || falls < least_each || s.rows.size() - falls < least_each) {
        note = "no search on outcomes: " + std::to_string(s.rows.size()) + " rows stood or fell (" + std::to_string(falls) +
               " fell); it needs " + std::to_string(least_rows) + ", at least " + std::to_string(least_each) + " of each";
        return std::nullopt;
    }
    s.input = input_rows(forces, s.rows);
    s.input.observed = Observed::outcome;
    for (std::size_t k = 0; k < s.rows.size(); ++k) {
        s.input.measured_gf[k] = *data.trials[s.rows[k]].outcome == "fell" ? 1.0 : 0.0;
        s.input.predicted_gf[k] = std::clamp(fall_probability[s.rows[k]], 0.0, 1.0);
    }
    AnalysisOptions o = options;
    o.outlier_z = 0.0; // a fall is 0 or 1: no gross errors among them
    if (o.progress) {
        o.progress = [progress = options.progress](const std::string& stage, std::uint32_t done, std::uint32_t of) { progress("outcomes: " + stage, done, of); };
    }
    auto analysis = analyse_discrepancy(s.input, o);
    if (!analysis) {
        note = "no search on outcomes: " + analysis.error().message;
        return std::nullopt;
    }
    s.analysis = std::move(analysis).value();
    // The analysis reports a term's effect as exp(change) - 1 (its force factor); on outcomes the change
    // itself is the change in the chance of falling.
    for (const Cause& c : s.analysis.causes) {
        OutcomeCause oc;
        oc.covariate = c.covariate;
        oc.category = c.category;
        oc.shape = c.shape.form;
        oc.x_low = c.x_low;
        oc.x_high = c.x_high;
        oc.effect = std::log1p(c.effect_size);
        oc.effect_low = std::log1p(c.effect_low);
        oc.effect_high = std::log1p(c.effect_high);
        oc.direction = oc.effect >= 0.0 ? "falls more" : "falls less";
        oc.p_value = c.p_value;
        s.causes.push_back(std::move(oc));
    }
    // Scored on the same rows: the simulation's chance, and the chance with the correction from the
    // fold that held each row out (nothing found: the same chance).
    std::vector<double> held_out = fall_probability;
    for (std::size_t k = 0; k < s.rows.size(); ++k) {
        const double g = s.analysis.discrepancy_found && k < s.analysis.cv_log_factor.size() ? s.analysis.cv_log_factor[k] : 0.0;
        held_out[s.rows[k]] = std::clamp(fall_probability[s.rows[k]] + g, 0.0, 1.0);
    }
    s.baseline = *score_outcomes(data, fall_probability);
    s.held_out = *score_outcomes(data, held_out);
    return s;
}

namespace {

// A file of several species: each species' held-out error without and with the extension found on
// all rows. Five per cent more error than the simulation alone is clearly worse; then the extension
// is no one's: each species is searched on its own rows, and each gets its own.
Result<void> check_each_species(ValidationResult& v, const std::vector<std::string>& row_species, const ValidationOptions& options) {
    std::map<std::string, std::vector<std::size_t>> rows_of;
    for (std::size_t i = 0; i < row_species.size(); ++i) rows_of[row_species[i]].push_back(i);
    std::vector<bool> aside(row_species.size(), false);
    for (const auto& r : v.analysis.suspected) aside[r.row] = true;
    for (const auto& [species, rows] : rows_of) {
        SpeciesCheck c;
        c.species = species;
        c.rows = rows.size();
        double without = 0.0, with = 0.0;
        std::size_t used = 0;
        for (const std::size_t i : rows) {
            if (aside[i]) continue;
            const double m = v.input.measured_gf[i], p = v.input.predicted_gf[i];
            without += (m - p) * (m - p);
            with += (m - p * std::exp(v.analysis.cv_log_factor[i])) * (m - p * std::exp(v.analysis.cv_log_factor[i]));
            ++used;
        }
        c.baseline_rmse_gf = std::sqrt(without / static_cast<double>(std::max<std::size_t>(used, 1)));
        c.shared_cv_rmse_gf = std::sqrt(with / static_cast<double>(std::max<std::size_t>(used, 1)));
        OtherMeasure m = judge_other_measure(species + "'s " + std::to_string(rows.size()) + " rows, held-out error in gf (the extension found on every species' rows)",
                                             0.0, c.baseline_rmse_gf, c.shared_cv_rmse_gf, 0.05 * c.baseline_rmse_gf);
        m.error = true;
        v.per_species = v.per_species || m.worse;
        v.others.push_back(std::move(m));
        v.by_species.push_back(std::move(c));
    }
    for (auto& c : v.by_species) {
        const std::vector<components::DeteriorationTerm>* extension = &v.analysis.extension;
        if (v.per_species) {
            const auto& rows = rows_of[c.species];
            if (rows.size() < 3) continue; // too few to search: nothing is written for it
            auto own = analyse_discrepancy(input_rows(v.input, rows), options.analysis);
            if (!own) return make_error(own.error().code, v.measured_file + ": the rows of " + c.species + ": " + own.error().message);
            c.own = std::move(own).value();
            extension = &c.own->extension;
        }
        if (extension->empty()) continue;
        auto json = extended_species_json(c.species, *extension, v.measured_file);
        if (!json) {
            // The analysis stands without the file: said, and the rest written.
            v.resimulation_note += (v.resimulation_note.empty() ? "" : "; ") + c.species + ": " + json.error().message + ", so no species file is written for it";
            continue;
        }
        c.extended_species_json = std::move(json).value();
    }
    return {};
}

} // namespace

std::string species_output_path(const std::string& path, const std::string& species) {
    // A species named by its file goes by the file's name; nothing in it may leave the folder.
    // The file's name is the species' id (`species check` holds every file to that), so it takes an id's
    // letters: lower case, digits, '-' and '_' ("ext.iris.json" was refused for its dot).
    std::string id = std::filesystem::path(species).stem().string();
    for (char& ch : id) {
        ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-') ch = '_';
    }
    const std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + "-" + id + p.extension().string())).string();
}

Result<std::string> extended_species_json(const std::string& species, const std::vector<components::DeteriorationTerm>& terms,
                                          const std::string& measured_file) {
    // The species file itself (resolved as every command resolves ids and paths), edited as JSON so
    // that everything the extension does not touch stays as the designer wrote it.
    auto def = load_species(species);
    if (!def) return std::move(def).error();
    const auto path = def->file;
    auto text = assets::read_text_file(path);
    if (!text) return std::move(text).error();
    nlohmann::json root = nlohmann::json::parse(*text, nullptr, false);
    if (root.is_discarded() || !root.is_object()) return make_error(ErrorCode::parse_error, path.string() + ": not a species object");
    nlohmann::json det = root.value("deterioration", nlohmann::json::object());
    nlohmann::json out_terms = nlohmann::json::array();
    std::string base = det.value("model", "paper_baseline");
    if (base == "extended") {
        base = det.value("base", "paper_baseline");
        if (det.contains("terms")) out_terms = det["terms"];
    }
    for (const auto& t : terms) out_terms.push_back(species_term_json(t));
    root["deterioration"] = {{"model", "extended"}, {"base", base}, {"terms", out_terms},
                             {"fitted_from", "ikebana validate " + measured_file},
                             {"notes", "The force the base model gives is multiplied by exp(sum of the terms); the level term "
                                       "is the overall calibration. Covariates the world does not have come from the trial row "
                                       "(predict) or from --env / the scene's \"environment\" block (the app)."}};
    const std::string id = root.value("id", std::string("species"));
    if (!id.ends_with("-extended")) root["id"] = id + "-extended";
    root["name"] = root.value("name", id) + " (extended by ikebana validate)";
    std::string json = assets::json_text(root, 2) + "\n";
    // Refuse to hand out a file the species loader would reject.
    auto check = parse_species(json, "extended species");
    if (!check) return make_error(ErrorCode::parse_error, "the extended species does not load: " + check.error().message);
    return json;
}

namespace {

// A species written where the predictor can load it (its caller removes it).
Result<std::string> temporary_species_file(const std::string& json) {
    char scratch[] = "/tmp/ikebana-species-XXXXXX";
    const int fd = mkstemp(scratch);
    if (fd < 0) return make_error(ErrorCode::io_error, "cannot create a temporary species file");
    close(fd);
    const std::string file = std::string(scratch) + ".json";
    std::error_code renamed;
    std::filesystem::rename(scratch, file, renamed);
    if (renamed) {
        std::filesystem::remove(scratch, renamed);
        return make_error(ErrorCode::io_error, "cannot create a temporary species file");
    }
    if (auto w = assets::write_text_file(file, json); !w) {
        std::filesystem::remove(file);
        return std::move(w).error();
    }
    return file;
}

// Each stood/fell row's chance at the hold_curve_factors, simulated (a species with that level on its
// holding; rows that share a push share the simulations), then the outcome search's terms fitted on
// those curves as terms on the holding. One species only: several would each need their own.
Result<void> fit_holding(ValidationResult& v, InsertionPredictor& predictor, const std::vector<InsertionConditions>& rows,
                         const std::vector<double>& baseline_fall, const ValidationOptions& options) {
    OutcomeSearch& s = *v.outcome_search;
    if (v.species.empty()) {
        s.hold_note = "the rows use several species: no holding is fitted (each species would need its own)";
        return {};
    }
    auto base = extended_species_json(v.species, {}, v.measured_file);
    if (!base) {
        s.hold_note = "no holding is fitted: " + base.error().message;
        return {};
    }
    // The species written is checked by running it (write_and_resimulate, within resimulate_limit
    // distinct conditions): a holding that could not be checked is not fitted at all.
    std::set<std::string> pushes;
    for (const std::size_t i : s.rows) pushes.insert(predictor.key(rows[i]));
    if (pushes.size() > options.resimulate_limit) {
        s.hold_note = "no holding is fitted: " + std::to_string(pushes.size()) + " distinct conditions among the stood/fell rows (limit " +
                      std::to_string(options.resimulate_limit) + ") to simulate it at " + std::to_string(std::size(hold_curve_factors)) + " holdings and check it";
        return {};
    }
    s.hold_fitted = true;
    // The stood/fell rows' chances of falling through the species with `terms` on its holding.
    const auto simulate = [&](const std::vector<components::DeteriorationTerm>& terms, const char* stage, std::size_t& done,
                              std::size_t of) -> Result<std::vector<double>> {
        auto json = with_hold_terms(*base, terms);
        if (!json) return std::move(json).error();
        auto written = temporary_species_file(*json);
        if (!written) return std::move(written).error();
        const std::string file = *written;
        std::vector<InsertionConditions> held;
        for (const std::size_t i : s.rows) {
            held.push_back(rows[i]);
            held.back().species = file;
        }
        std::vector<double> chance(held.size(), 0.0);
        for (const std::size_t k : predictor.simulation_order(held)) {
            const auto p = predictor.predict(held[k]);
            if (!p) {
                std::filesystem::remove(file);
                return make_error(p.error().code, v.measured_file + ":" + std::to_string(v.data.trials[s.rows[k]].line) + ": " + p.error().message);
            }
            chance[k] = p->fall_probability;
            if (options.progress) options.progress(stage, ++done, of);
        }
        std::filesystem::remove(file);
        return chance;
    };
    const auto add_point = [](HoldCurve& c, double x, double chance) {
        const auto at = std::lower_bound(c.log_factor.begin(), c.log_factor.end(), x) - c.log_factor.begin();
        if (static_cast<std::size_t>(at) < c.log_factor.size() && std::abs(c.log_factor[static_cast<std::size_t>(at)] - x) < 1e-9) return;
        c.log_factor.insert(c.log_factor.begin() + at, x);
        c.chance.insert(c.chance.begin() + at, chance);
    };
    std::vector<HoldCurve> curves(s.rows.size());
    for (std::size_t k = 0; k < s.rows.size(); ++k) add_point(curves[k], 0.0, baseline_fall[s.rows[k]]);
    std::size_t done = 0;
    const std::size_t of = s.rows.size() * std::size(hold_curve_factors);
    for (const double factor : hold_curve_factors) {
        components::DeteriorationTerm level{};
        level.covariate = "level";
        level.form = "constant";
        level.coefficient = std::log(factor);
        auto chance = simulate({level}, "simulating the holding", done, of);
        if (!chance) return std::move(chance).error();
        for (std::size_t k = 0; k < s.rows.size(); ++k) add_point(curves[k], std::log(factor), (*chance)[k]);
    }
    // The fit reads each row's chance at the nearest simulated factor, and with several terms it can
    // find factors between the simulated ones where that reading is wrong (a fit promising log-loss
    // 0.36 gave 1.15 when its species was run). So the fitted species is run, each row's chance at the
    // factor the fit gave it joins that row's curve, and the terms are fitted again: at most
    // hold_refinements times, keeping the terms whose simulation predicted the falls best.
    constexpr int hold_refinements = 3;
    double best_simulated = INFINITY;
    std::size_t refined = 0;
    for (int round = 0; round <= hold_refinements; ++round) {
        double fit_loss = 0.0;
        auto terms = fit_hold_terms(v.data, s.rows, s.analysis.extension, curves, &fit_loss);
        if (terms.empty()) break;
        auto chance = simulate(terms, "checking the holding", refined, s.rows.size() * (hold_refinements + 1));
        if (!chance) return std::move(chance).error();
        double simulated = 0.0;
        for (std::size_t k = 0; k < s.rows.size(); ++k) {
            const std::size_t i = s.rows[k];
            simulated += row_log_loss((*chance)[k], *v.data.trials[i].outcome == "fell");
            add_point(curves[k], std::log(systems::insertion::extension_factor(terms, v.data.trials[i].insertion, v.data.covariates_of(i))), (*chance)[k]);
        }
        simulated /= static_cast<double>(std::max<std::size_t>(s.rows.size(), 1));
        if (simulated < best_simulated) {
            best_simulated = simulated;
            s.hold_terms = std::move(terms);
            s.hold_fit_log_loss = fit_loss;
        }
        // Its promise kept (within 0.02): another round would only refit the same.
        if (std::abs(simulated - fit_loss) < 0.02) break;
    }
    return {};
}

} // namespace

namespace {

// The extended species (the forces' terms, and `hold_terms` on the holding) written, checked to load,
// and run back through the simulation for every row when there are few enough distinct conditions.
Result<void> write_and_resimulate(ValidationResult& v, InsertionPredictor& predictor, const ValidationOptions& options,
                                  const std::vector<components::DeteriorationTerm>& hold_terms) {
    const std::string& measured_path = v.measured_file;
    const std::size_t n_rows = v.data.trials.size();
    const bool outcomes = v.data.has_outcome;
    auto json = extended_species_json(v.species, v.analysis.extension, measured_path);
    if (json && !hold_terms.empty()) json = with_hold_terms(*json, hold_terms);
    if (!json) {
        // A check that the written species loads never costs the analysis: said, and the rest written.
        v.resimulation_note = json.error().message + ", so no species file is written and the simulation is not run again with it";
        return {};
    }
    v.extended_species_json = *json;

    // The extended species back through the simulation, row by row.
    auto written = temporary_species_file(v.extended_species_json);
    if (!written) return std::move(written).error();
    const std::string temporary = *written;
    // Each row's conditions once: counted here, simulated below when there are few enough.
    std::vector<InsertionConditions> extended_rows;
    extended_rows.reserve(n_rows);
    for (std::size_t i = 0; i < n_rows; ++i) extended_rows.push_back(predictor.conditions_of(v.data, i, temporary, outcomes));
    std::set<std::string> distinct;
    for (const auto& c : extended_rows) distinct.insert(predictor.key(c));
    if (distinct.size() > options.resimulate_limit) {
        v.resimulation_note = std::to_string(distinct.size()) + " distinct conditions for the extended species (limit " +
                              std::to_string(options.resimulate_limit) + "): not re-simulated here; `ikebana predict --species EXT.json` does it";
    } else {
        std::vector<double> fall(v.data.trials.size(), 0.0);
        double sum = 0.0;
        // On the rows the analysis used: a row set aside as a gross error is not the model's to explain.
        std::vector<bool> aside(v.data.trials.size(), false);
        for (const auto& r : v.analysis.suspected) aside[r.row] = true;
        std::size_t used = 0;
        const auto extended_order = predictor.simulation_order(extended_rows);
        v.simulated_extended_gf.assign(n_rows, 0.0);
        for (std::size_t n = 0; n < n_rows; ++n) {
            const std::size_t i = extended_order[n];
            const auto& t = v.data.trials[i];
            const auto p = predictor.predict(extended_rows[i]);
            if (!p) {
                std::filesystem::remove(temporary);
                return make_error(p.error().code, measured_path + ":" + std::to_string(t.line) + ": " + p.error().message);
            }
            const double gf = p->max_force_n / gram_force_n;
            v.simulated_extended_gf[i] = gf;
            if (!aside[i]) {
                sum += (t.max_force_gf - gf) * (t.max_force_gf - gf);
                ++used;
            }
            fall[i] = p->fall_probability;
            if (options.progress) options.progress("simulating the extended species", n + 1, n_rows);
        }
        v.simulated_extended_rmse_gf = std::sqrt(sum / static_cast<double>(std::max<std::size_t>(used, 1)));
        if (outcomes) {
            v.extended_outcome = score_outcomes(v.data, fall);
            v.extended_fall_probability = fall;
        }
        // Stood or fell, row by row: a perfect model is right on every row; five points of accuracy
        // lost is clearly worse.
        if (v.baseline_outcome && v.extended_outcome)
            v.others.push_back(judge_other_measure("outcome accuracy (share of rows whose stood/fell it gets right)", 1.0, v.baseline_outcome->accuracy,
                                                   v.extended_outcome->accuracy, 0.05));
        // The holding fitted to the falls, against the forces: a term on the holding never touches the
        // push, so they must not move; 5 % more error is clearly worse.
        if (!hold_terms.empty() && v.analysis.extension.empty()) {
            OtherMeasure m = judge_other_measure("force RMSE through the simulation (gf), with the holding fitted to the falls", 0.0, v.analysis.baseline_rmse_gf,
                                                 *v.simulated_extended_rmse_gf, 0.05 * v.analysis.baseline_rmse_gf);
            m.error = true;
            v.others.push_back(m);
        }
    }
    std::filesystem::remove(temporary);
    return {};
}


} // namespace

Result<ValidationResult> run_validation(const std::string& measured_path, const ValidationOptions& options) {
    ValidationResult v;
    v.measured_file = measured_path;
    auto data = load_measured_data(measured_path);
    if (!data) return std::move(data).error();
    v.data = std::move(data).value();
    if (v.data.trials.size() < 3) return make_error(ErrorCode::invalid_argument, measured_path + ": at least 3 trials are needed");
    auto covariates = candidate_covariates(v.data.table, options.ignore);
    if (!covariates) return std::move(covariates).error();

    std::set<std::string> species;
    for (const auto& t : v.data.trials) species.insert(!options.species_override.empty() ? options.species_override : t.species.value_or("sunflower"));
    v.species = species.size() == 1 ? *species.begin() : std::string();

    // The baseline: every row through the live systems.
    InsertionPredictor predictor;
    const bool outcomes = v.data.has_outcome;
    const std::size_t n_rows = v.data.trials.size();
    std::vector<double> baseline_fall(n_rows, 0.0);
    v.input.flower.resize(n_rows);
    v.input.measured_gf.resize(n_rows);
    v.input.predicted_gf.resize(n_rows);
    std::vector<InsertionConditions> rows;
    rows.reserve(n_rows);
    for (std::size_t i = 0; i < n_rows; ++i) rows.push_back(predictor.conditions_of(v.data, i, options.species_override, outcomes));
    const auto order = predictor.simulation_order(rows); // each distinct simulation once, whatever the rows' order
    for (std::size_t n = 0; n < n_rows; ++n) {
        const std::size_t i = order[n];
        const auto& t = v.data.trials[i];
        const auto p = predictor.predict(rows[i]);
        if (!p) return make_error(p.error().code, measured_path + ":" + std::to_string(t.line) + ": " + p.error().message);
        v.input.flower[i] = t.flower_id;
        v.input.measured_gf[i] = t.max_force_gf;
        v.input.predicted_gf[i] = std::max(p->max_force_n / gram_force_n, 1e-6);
        baseline_fall[i] = p->fall_probability;
        if (options.progress) options.progress("simulating the baseline", n + 1, n_rows);
    }
    v.input.covariates = std::move(covariates).value();
    auto analysis = analyse_discrepancy(v.input, options.analysis);
    if (!analysis) return std::move(analysis).error();
    v.analysis = std::move(analysis).value();
    for (const auto& c : v.analysis.causes) v.explanations.push_back(explain_cause(c));
    if (!v.analysis.rows_as_groups) {
        // Each row's residual after the fitted model, the rows set aside as gross errors left out.
        std::vector<bool> aside(n_rows, false);
        for (const auto& r : v.analysis.suspected) aside[r.row] = true;
        std::vector<std::string> who;
        std::vector<double> residual;
        for (std::size_t i = 0; i < n_rows; ++i) {
            if (aside[i]) continue;
            const double model = i < v.analysis.fitted_log_factor.size() ? v.analysis.fitted_log_factor[i] : 0.0;
            who.push_back(v.input.flower[i]);
            residual.push_back(std::log(v.input.measured_gf[i] / v.input.predicted_gf[i]) - model);
        }
        v.spread = flower_spread(who, residual);
    }
    if (outcomes) {
        v.baseline_outcome = score_outcomes(v.data, baseline_fall);
        v.baseline_fall_probability = baseline_fall;
        v.outcome_search = search_outcomes(v.data, v.input, baseline_fall, options.analysis, v.outcome_note);
        if (v.outcome_search && v.outcome_search->analysis.discrepancy_found) {
            if (auto fitted = fit_holding(v, predictor, rows, baseline_fall, options); !fitted) return std::move(fitted).error();
        }
    }
    const std::vector<components::DeteriorationTerm> no_terms;
    const auto& hold_terms = v.outcome_search ? v.outcome_search->hold_terms : no_terms;

    if (v.analysis.extension.empty() && hold_terms.empty()) return v;
    if (v.species.empty() && v.analysis.extension.empty()) {
        v.resimulation_note = "the rows use several species: the holding fitted to the falls is not written per species";
        return v;
    }
    if (v.species.empty()) {
        std::vector<std::string> row_species(n_rows);
        for (std::size_t i = 0; i < n_rows; ++i) row_species[i] = rows[i].species;
        if (auto checked = check_each_species(v, row_species, options); !checked) return std::move(checked).error();
        v.resimulation_note = "the rows use several species: an extended species per species, not re-simulated here (`ikebana predict --species` with each)";
        return v;
    }
    if (auto written = write_and_resimulate(v, predictor, options, hold_terms); !written) return std::move(written).error();
    // A holding fitted to the falls must predict them better through the simulation than without it
    // (the fit runs on simulated curves, the check on the species itself): otherwise it is left out.
    const bool unchecked = !hold_terms.empty() && !v.extended_outcome;
    if (unchecked || (!hold_terms.empty() && v.baseline_outcome && v.extended_outcome && v.extended_outcome->log_loss > v.baseline_outcome->log_loss)) {
        OutcomeSearch& s = *v.outcome_search;
        s.hold_rejected = true;
        if (unchecked) s.hold_note = "the holding fitted to the falls could not be run through the simulation (" + v.resimulation_note + "), so it is not written";
        else s.hold_simulated = *v.extended_outcome;
        v.extended_species_json.clear();
        v.simulated_extended_gf.clear();
        v.simulated_extended_rmse_gf.reset();
        v.extended_outcome.reset();
        v.extended_fall_probability.clear();
        v.others.clear();
        v.resimulation_note.clear();
        if (!v.analysis.extension.empty()) {
            if (auto written = write_and_resimulate(v, predictor, options, {}); !written) return std::move(written).error();
        }
    }
    return v;
}

OtherMeasure judge_other_measure(std::string name, double measured, double baseline, double extended, double tolerance) {
    OtherMeasure m{std::move(name), measured, baseline, extended, tolerance, false};
    m.worse = std::abs(extended - measured) > std::abs(baseline - measured) + tolerance;
    return m;
}

std::string other_measure_words(const OtherMeasure& m) {
    char text[512];
    if (m.error) {
        std::snprintf(text, sizeof text, "%s: %.3g with the extension, %.3g without: %s", m.name.c_str(), m.extended, m.baseline,
                      m.worse ? "the extension makes it clearly worse, so it is no improvement here"
                              : (m.extended < m.baseline ? "the extension lowers it" : "about as before"));
        return text;
    }
    std::snprintf(text, sizeof text, "%s: extended %.3g against the measured %.3g (the baseline %.3g): %s", m.name.c_str(), m.extended, m.measured, m.baseline,
                  m.worse ? "the extension makes it clearly worse, so it is no improvement here"
                          : (std::abs(m.extended - m.measured) < std::abs(m.baseline - m.measured) ? "the extension brings it nearer" : "about as before"));
    return text;
}

Result<std::string> extended_species_applied_to(const std::string& species_json, const std::string& applies_to) {
    auto root = nlohmann::ordered_json::parse(species_json, nullptr, false);
    if (root.is_discarded() || !root.contains("deterioration")) return make_error(ErrorCode::invalid_argument, "not an extended species");
    root["deterioration"]["applies_to"] = applies_to;
    std::string json = assets::json_text(root, 2) + "\n";
    if (auto check = parse_species(json, "extended species"); !check) return make_error(ErrorCode::parse_error, "the extended species does not load: " + check.error().message);
    return json;
}

} // namespace ikebana::game
