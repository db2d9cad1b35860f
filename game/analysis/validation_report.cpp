#include "game/analysis/validation_report.hpp"

#include "engine/core/utf8.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/analysis/cause_explanations.hpp"
#include "game/analysis/svg_plot.hpp"

namespace ikebana::game {

namespace {

// Text from the data in a Markdown table's cell: a '|' or a line break would split the table, and
// '<', '>' and '&' would reach a renderer as HTML; control characters are shown, not kept.
// Text from the data in Markdown prose (a heading, a list item): HTML shown as text, one line.
std::string prose(const std::string& text) {
    std::string out;
    for (const char ch : terminal_text(text)) {
        switch (ch) {
        case '\n':
        case '\r': out += ' '; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '&': out += "&amp;"; break;
        default: out += ch;
        }
    }
    return out;
}

std::string cell(const std::string& text) {
    std::string out;
    for (const char ch : terminal_text(text)) {
        switch (ch) {
        case '|': out += "\\|"; break;
        case '\n':
        case '\r':
        case '\t': out += ' '; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '&': out += "&amp;"; break;
        case '`': out += "'"; break; // inside a code span a backtick would end it
        default: out += ch;
        }
    }
    return out;
}


double finite_or_zero(double v) { return std::isfinite(v) ? v : 0.0; }

std::string fmt(const char* format, double v) {
    char text[64];
    std::snprintf(text, sizeof text, format, v);
    return text;
}

std::string file_safe(const std::string& name) {
    std::string out;
    for (char c : name) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
    return out;
}

const CovariateColumn* column_named(const ValidationResult& v, const std::string& name) {
    for (const auto& c : v.input.covariates.columns) {
        if (c.name == name) return &c;
    }
    return nullptr;
}

const Cause* cause_named(const ValidationResult& v, const std::string& name) {
    for (const auto& c : v.analysis.causes) {
        if (c.covariate == name) return &c;
    }
    return nullptr;
}

bool flagged(const CovariateDiagnostic& d, double alpha) { return d.cause || d.p_adjusted <= alpha || d.p_given_model <= alpha; }

// The predicted chance of falling against the share that fell, by bins of the chance: baseline and
// extended species, each bin's share with ±2 binomial standard errors; a calibrated model is on the diagonal.
std::string calibration_chart(const ValidationResult& v) {
    SvgChart chart;
    chart.title = "predicted chance of falling against the share that fell";
    chart.x_label = "predicted chance of falling (bin mean)";
    chart.y_label = "share of the rows that fell";
    chart.identity_line = true;
    const auto series_of = [&](const std::vector<double>& chance, const char* label, const char* colour, const char* marker) {
        SvgSeries s{label, colour, {}, {}, {}, {}, true, 4.0, 0.9, marker, {}};
        for (const auto& b : calibration_bins(v.data, chance)) {
            s.x.push_back(b.predicted);
            s.y.push_back(b.fell);
            s.low.push_back(std::max(0.0, b.fell - 2.0 * b.se));
            s.high.push_back(std::min(1.0, b.fell + 2.0 * b.se));
            s.labels.push_back(std::to_string(b.rows));
        }
        return s;
    };
    chart.series.push_back(series_of(v.baseline_fall_probability, "baseline species (±2 s.e.; beside each: its rows)", "#7f7f7f", "circle"));
    if (!v.extended_fall_probability.empty()) chart.series.push_back(series_of(v.extended_fall_probability, "extended species", "#1f77b4", "square"));
    return render_svg(chart);
}

std::string residual_chart(const ValidationResult& v, const CovariateDiagnostic& d) {
    const CovariateColumn& column = *column_named(v, d.covariate);
    SvgChart chart;
    chart.title = "measured / simulated against " + d.covariate;
    chart.x_label = d.covariate;
    chart.y_label = "measured / simulated force";
    chart.log_y = true;
    chart.reference_y = {1.0};
    SvgSeries rows{"trials", "#7f7f7f", {}, {}, {}, {}, false, 2.0, 0.35, "circle", {}};
    for (std::size_t i = 0; i < v.input.measured_gf.size(); ++i) {
        // Discrete columns get a little deterministic jitter so that the rows do not hide each other.
        const double jitter = (static_cast<double>((i * 2654435761U) % 1000) / 1000.0 - 0.5) * 0.25;
        rows.x.push_back(column.numeric ? column.values[i] : static_cast<double>(column.level[i]) + jitter);
        rows.y.push_back(v.input.measured_gf[i] / v.input.predicted_gf[i]);
    }
    if (!column.numeric) chart.x_categories = column.levels;
    // A bin of one trial has no spread to show: it is drawn apart, without an interval.
    SvgSeries bins{"binned mean (±2 s.e.)", "#d62728", {}, {}, {}, {}, false, 4.0, 1.0, "circle", {}};
    SvgSeries single{"a single trial (no interval)", "#d62728", {}, {}, {}, {}, false, 4.0, 0.45, "square", {}};
    for (const auto& b : d.bins) {
        SvgSeries& into = b.n > 1 ? bins : single;
        into.x.push_back(b.x);
        into.y.push_back(b.factor);
        if (b.n > 1) {
            bins.low.push_back(b.low);
            bins.high.push_back(b.high);
        }
    }
    chart.series.push_back(rows);
    if (!bins.x.empty()) chart.series.push_back(bins);
    if (!single.x.empty()) chart.series.push_back(single);
    if (const Cause* c = cause_named(v, d.covariate)) {
        // The fitted term at the overall level, for comparison with the binned means.
        SvgSeries fit{"extension (" + c->shape.form + ")", "#1f77b4", {}, {}, {}, {}, column.numeric, column.numeric ? 0.0 : 5.0, 1.0, "circle", {}};
        const double level = std::exp(v.analysis.extension.front().coefficient);
        for (std::size_t k = 0; k < c->curve_x.size(); ++k) {
            fit.x.push_back(c->curve_x[k]);
            fit.y.push_back(level * c->curve_factor[k]);
        }
        chart.series.push_back(fit);
    }
    return render_svg(chart);
}

// What the simulation gets wrong about falls against a column: each row's fell minus its chance (jittered),
// the binned means with +-2 s.e., and the correction the outcome search fitted (a cause's).
std::string outcome_chart(const OutcomeSearch& s, const CovariateDiagnostic& d) {
    const CovariateColumn* column = nullptr;
    for (const auto& c : s.input.covariates.columns) {
        if (c.name == d.covariate) column = &c;
    }
    SvgChart chart;
    chart.title = "fell minus the simulated chance of falling, against " + d.covariate;
    chart.x_label = d.covariate;
    chart.y_label = "fell (1) or stood (0), minus the chance";
    chart.reference_y = {0.0};
    SvgSeries rows{"trials", "#7f7f7f", {}, {}, {}, {}, false, 2.0, 0.3, "circle", {}};
    for (std::size_t i = 0; column && i < s.input.measured_gf.size(); ++i) {
        const double jitter = (static_cast<double>((i * 2654435761U) % 1000) / 1000.0 - 0.5) * 0.25;
        rows.x.push_back(column->numeric ? column->values[i] : static_cast<double>(column->level[i]) + jitter);
        rows.y.push_back(s.input.measured_gf[i] - s.input.predicted_gf[i]);
    }
    if (column && !column->numeric) chart.x_categories = column->levels;
    // The bins carry exp(mean residual) (the forces' factor): their log is the mean of fell - chance.
    SvgSeries bins{"binned mean (±2 s.e.)", "#d62728", {}, {}, {}, {}, false, 4.0, 1.0, "circle", {}};
    for (const auto& b : d.bins) {
        if (b.n < 2) continue;
        bins.x.push_back(b.x);
        bins.y.push_back(std::log(b.factor));
        bins.low.push_back(std::log(b.low));
        bins.high.push_back(std::log(b.high));
    }
    chart.series.push_back(rows);
    if (!bins.x.empty()) chart.series.push_back(bins);
    for (const auto& c : s.analysis.causes) {
        if (c.covariate != d.covariate || !column || !column->numeric) continue;
        const double level = s.analysis.extension.empty() ? 0.0 : s.analysis.extension.front().coefficient;
        SvgSeries fit{"correction (" + c.shape.form + ")", "#1f77b4", {}, {}, {}, {}, true, 0.0, 1.0, "circle", {}};
        for (std::size_t k = 0; k < c.curve_x.size(); ++k) {
            fit.x.push_back(c.curve_x[k]);
            fit.y.push_back(level + std::log(c.curve_factor[k]));
        }
        chart.series.push_back(fit);
    }
    return render_svg(chart);
}

// report.md's section on the outcome search: its causes, a figure per cause, and the held-out scores.
std::string outcome_markdown(const ValidationResult& v, std::vector<std::pair<std::string, std::string>>& figures) {
    std::ostringstream md;
    md << "### What the simulation gets wrong about falls\n\n";
    if (!v.outcome_search) {
        md << prose(v.outcome_note) << ".\n\n";
        return md.str();
    }
    const OutcomeSearch& s = *v.outcome_search;
    md << "Every column was tested against each row's fall (1) or stand (0) minus the simulated chance of falling, as the forces are: "
          "flowers kept together in the permutations, family-wise control, shapes chosen by grouped cross-validation on the log-loss, "
          "a backward pass, and intervals from resampled flowers. An effect is the change in the chance of falling across the column "
          "(its 5th to 95th percentile).\n\n";
    if (s.causes.empty()) {
        md << (s.analysis.discrepancy_found ? "No column: only an overall level (the flowers fall more or less often than simulated, whatever the column).\n\n"
                                            : "No column explains the wrong falls beyond chance after correction.\n\n");
    } else {
        md << "| column | direction | shape | change in the chance of falling | 95 % interval | across | p |\n|---|---|---|---|---|---|---|\n";
        for (const auto& c : s.causes) {
            md << "| `" << cell(c.covariate) << (c.category.empty() ? "" : " = " + cell(c.category)) << "` | " << c.direction << " | " << c.shape << " | "
               << fmt("%+.3f", c.effect) << " | " << fmt("%+.3f", c.effect_low) << " to " << fmt("%+.3f", c.effect_high) << " | "
               << (c.category.empty() ? fmt("%.4g", c.x_low) + " to " + fmt("%.4g", c.x_high) : std::string("that level against the others")) << " | "
               << fmt("%.3g", c.p_value) << " |\n";
        }
        md << "\n";
    }
    for (const auto& d : s.analysis.diagnostics) {
        if (!d.cause) continue;
        const std::string name = "outcome_" + file_safe(d.covariate) + ".svg";
        figures.emplace_back(name, outcome_chart(s, d));
        md << "![wrong falls against " << cell(d.covariate) << "](" << name << ")\n\n";
    }
    md << "Held out (each row scored by the correction's coefficients fitted without its fold; its columns and shapes were chosen on "
          "every row, so this is somewhat optimistic): log-loss " << fmt("%.3f", s.baseline.log_loss) << " → "
       << fmt("%.3f", s.held_out.log_loss) << ", Brier " << fmt("%.3f", s.baseline.brier) << " → " << fmt("%.3f", s.held_out.brier) << ", accuracy "
       << fmt("%.1f %%", 100 * s.baseline.accuracy) << " → " << fmt("%.1f %%", 100 * s.held_out.accuracy) << ".\n\n";
    if (!s.hold_terms.empty()) {
        md << "**As a holding the simulation runs.** The correction's terms, refitted as terms on what holds a stem at rest "
              "(`\"applies_to\": \"hold\"`: the holding moment times exp(sum), the push untouched), on each row's chance of falling "
              "simulated with its holding at 0.5 to 2 times (a row's chance at a factor: the nearest simulated factor's):\n\n"
              "| covariate | form | coefficient | scale | origin |\n|---|---|---|---|---|\n";
        for (const auto& t : s.hold_terms) {
            md << "| `" << cell(t.covariate) << "` | " << t.form << " | " << fmt("%.5g", t.coefficient) << " | " << fmt("%.5g", t.scale) << " | "
               << fmt("%.5g", t.origin) << " |\n";
        }
        if (s.hold_rejected && !s.hold_note.empty()) {
            md << "\n" << prose(s.hold_note) << ".\n\n";
        } else if (s.hold_rejected) {
            md << "\nRun through the simulation it predicted the falls worse (log-loss " << fmt("%.3f", s.hold_simulated.log_loss) << ", without it "
               << fmt("%.3f", v.baseline_outcome ? v.baseline_outcome->log_loss : 0.0) << "), so it is not in the species written.\n\n";
        } else if (v.baseline_outcome && v.extended_outcome) {
            md << "\nThe extended species run through the simulation on every stood/fell row: log-loss " << fmt("%.3f", v.baseline_outcome->log_loss) << " → "
               << fmt("%.3f", v.extended_outcome->log_loss) << ", Brier " << fmt("%.3f", v.baseline_outcome->brier) << " → "
               << fmt("%.3f", v.extended_outcome->brier) << ", accuracy " << fmt("%.1f %%", 100 * v.baseline_outcome->accuracy) << " → "
               << fmt("%.1f %%", 100 * v.extended_outcome->accuracy) << " (in sample: the terms were fitted on these rows).\n\n";
        }
    }
    return md.str();
}

std::string model_chart(const ValidationResult& v) {
    SvgChart chart;
    chart.title = "simulation against measurement";
    chart.x_label = "measured maximum force (gf)";
    chart.y_label = "simulated maximum force (gf)";
    chart.log_x = chart.log_y = true;
    chart.identity_line = true;
    // Three marker shapes (the extended model and its simulation often fall on each other) and, for a
    // file small enough to read them, each point's insertion number.
    const std::size_t rows = v.input.measured_gf.size();
    const bool numbered = rows <= 60;
    if (numbered) chart.title += " (numbers: the insertion)";
    SvgSeries before{"baseline simulation", "#ff7f0e", {}, {}, {}, {}, false, 3.0, 0.7, "circle", {}};
    SvgSeries after{"extended model (fit)", "#1f77b4", {}, {}, {}, {}, false, 3.0, 0.7, "square", {}};
    SvgSeries simulated{"extended species, simulated", "#2ca02c", {}, {}, {}, {}, false, 3.5, 0.7, "triangle", {}};
    for (std::size_t i = 0; i < rows; ++i) {
        if (numbered) before.labels.push_back(std::to_string(v.data.trials[i].insertion));
        before.x.push_back(v.input.measured_gf[i]);
        before.y.push_back(v.input.predicted_gf[i]);
        if (!v.analysis.extension.empty()) {
            after.x.push_back(v.input.measured_gf[i]);
            after.y.push_back(v.input.predicted_gf[i] * std::exp(v.analysis.fitted_log_factor[i]));
        }
        if (i < v.simulated_extended_gf.size()) {
            if (numbered) simulated.labels.push_back(std::to_string(v.data.trials[i].insertion));
            simulated.x.push_back(v.input.measured_gf[i]);
            simulated.y.push_back(v.simulated_extended_gf[i]);
        }
    }
    // The rows set aside as gross errors, ringed: the figures leave them out.
    SvgSeries aside{"set aside (suspected gross error)", "#d62728", {}, {}, {}, {}, false, 7.0, 0.25, "circle", {}};
    for (const auto& r : v.analysis.suspected) {
        aside.x.push_back(v.input.measured_gf[r.row]);
        aside.y.push_back(v.input.predicted_gf[r.row]);
    }
    if (!aside.x.empty()) chart.series.push_back(aside);
    chart.series.push_back(before);
    if (!after.x.empty()) chart.series.push_back(after);
    if (!simulated.x.empty()) chart.series.push_back(simulated);
    return render_svg(chart);
}

nlohmann::ordered_json term_json(const components::DeteriorationTerm& t) {
    nlohmann::ordered_json j = {{"covariate", t.covariate}, {"form", t.form}, {"coefficient", t.coefficient}, {"scale", t.scale}, {"origin", t.origin}};
    if (t.form == "category") j["category"] = t.category;
    if (t.range_high > t.range_low) j["range"] = {t.range_low, t.range_high};
    if (!t.times_covariate.empty()) j["times"] = {{"covariate", t.times_covariate}, {"origin", t.times_origin}, {"range", {t.times_low, t.times_high}}};
    return j;
}

} // namespace

nlohmann::ordered_json other_measurements_json(const std::vector<OtherMeasure>& others) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const auto& m : others) {
        list.push_back({{"name", m.name}, {"measured", m.measured}, {"baseline", m.baseline}, {"extended", m.extended}, {"tolerance", m.tolerance}, {"worse", m.worse}});
    }
    return list;
}

namespace {

void add_outcome_scores(nlohmann::ordered_json& into, const OutcomeScores& s) {
    into["outcome_accuracy"] = s.accuracy;
    into["outcome_brier"] = s.brier;
    into["outcome_log_loss"] = s.log_loss;
    into["outcome_rows"] = s.rows;
}

std::string outcome_words(const OutcomeScores& s) {
    return ", outcome accuracy " + fmt("%.0f %%", 100 * s.accuracy) + ", Brier " + fmt("%.3f", s.brier) + ", log-loss " + fmt("%.3f", s.log_loss);
}

} // namespace

std::string validation_json(const ValidationResult& v, const AnalysisOptions& options) {
    const AnalysisResult& a = v.analysis;
    nlohmann::ordered_json j;
    j["n_trials"] = a.n_trials;
    j["n_flowers"] = a.n_flowers;
    j["measured_file"] = v.measured_file;
    j["species"] = v.species;
    j["rows_stand_in_for_flowers"] = a.rows_as_groups;
    j["baseline"] = {{"rmse_gf", a.baseline_rmse_gf}, {"cv_rmse_gf", a.baseline_cv_rmse_gf}, {"log_rmse", a.baseline_log_rmse}};
    if (v.baseline_outcome) add_outcome_scores(j["baseline"], *v.baseline_outcome);
    if (v.spread) {
        j["flower_spread"] = {{"sd_log", v.spread->sd_log}, {"sd_percent", 100.0 * (std::exp(v.spread->sd_log) - 1.0)},
                              {"within_sd_log", v.spread->within_sd_log}, {"flowers", v.spread->flowers}, {"rows", v.spread->rows}};
    } else {
        j["flower_spread"] = nullptr;
    }
    j["discrepancy_found"] = a.discrepancy_found;
    j["calibration"] = {{"factor", a.calibration.factor}, {"interval", {finite_or_zero(a.calibration.low), finite_or_zero(a.calibration.high)}},
                        {"p_value", a.calibration.p_value}, {"significant", a.calibration.significant}};
    j["causes"] = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < a.causes.size(); ++k) {
        const Cause& c = a.causes[k];
        nlohmann::ordered_json cj = {{"covariate", c.covariate},
                             {"direction", c.direction},
                             {"shape", c.shape.form},
                             {"shape_detail", describe_shape(c.shape)},
                             {"effect_size", c.effect_size},
                             {"effect_interval", {finite_or_zero(c.effect_low), finite_or_zero(c.effect_high)}},
                             {"p_value", c.p_value},
                             {"importance", c.importance},
                             {"explanation", v.explanations[k]}};
        if (c.shape.form == "category") {
            cj["category"] = c.category;
            cj["reference"] = c.reference;
        } else {
            cj["range"] = {c.x_low, c.x_high};
        }
        j["causes"].push_back(cj);
    }
    j["extended"] = {{"cv_rmse_gf", a.extended_cv_rmse_gf}, {"gain", a.gain}, {"rmse_gf", a.extended_rmse_gf}, {"log_rmse", a.extended_log_rmse}};
    j["extended"]["terms"] = nlohmann::ordered_json::array();
    for (const auto& t : a.extension) j["extended"]["terms"].push_back(term_json(t));
    if (v.simulated_extended_rmse_gf) j["extended"]["simulated_rmse_gf"] = *v.simulated_extended_rmse_gf;
    if (v.extended_outcome) add_outcome_scores(j["extended"], *v.extended_outcome);
    if (!v.resimulation_note.empty()) j["extended"]["note"] = v.resimulation_note;
    if (v.outcome_search) {
        const OutcomeSearch& s = *v.outcome_search;
        j["outcome_causes"] = nlohmann::ordered_json::array();
        for (const auto& c : s.causes) {
            nlohmann::ordered_json cj{{"covariate", c.covariate}, {"direction", c.direction}, {"shape", c.shape}};
            if (!c.category.empty()) cj["category"] = c.category;
            else cj["range"] = {c.x_low, c.x_high};
            cj["effect"] = finite_or_zero(c.effect);
            cj["interval"] = {finite_or_zero(c.effect_low), finite_or_zero(c.effect_high)};
            cj["p_value"] = c.p_value;
            j["outcome_causes"].push_back(cj);
        }
        j["outcome_search"] = {{"rows", s.rows.size()}, {"flowers", s.analysis.n_flowers}, {"discrepancy_found", s.analysis.discrepancy_found},
                               {"level", s.analysis.calibration.significant ? std::log(s.analysis.calibration.factor) : 0.0},
                               {"baseline_log_loss", s.baseline.log_loss}, {"baseline_brier", s.baseline.brier},
                               {"held_out_log_loss", s.held_out.log_loss}, {"held_out_brier", s.held_out.brier}, {"held_out_accuracy", s.held_out.accuracy}};
        j["outcome_search"]["diagnostics"] = nlohmann::ordered_json::array();
        for (const auto& d : s.analysis.diagnostics) {
            j["outcome_search"]["diagnostics"].push_back({{"covariate", d.covariate}, {"p_value", d.p_value}, {"p_adjusted", d.p_adjusted},
                                                          {"p_given_model", d.p_given_model}, {"best_shape", d.best_shape}, {"cause", d.cause}});
        }
        j["outcome_search"]["log"] = s.analysis.log;
        j["outcome_search"]["hold_terms"] = nlohmann::ordered_json::array();
        for (const auto& t : s.hold_terms) j["outcome_search"]["hold_terms"].push_back(term_json(t));
        j["outcome_search"]["hold_fit_log_loss"] = s.hold_terms.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s.hold_fit_log_loss);
        j["outcome_search"]["hold_rejected"] = s.hold_rejected;
        if (!s.hold_note.empty()) j["outcome_search"]["hold_note"] = s.hold_note;
        if (s.hold_rejected && s.hold_note.empty()) {
            nlohmann::ordered_json scores;
            add_outcome_scores(scores, s.hold_simulated);
            j["outcome_search"]["hold_simulated"] = scores;
        }
    } else if (v.baseline_outcome) {
        j["outcome_causes"] = nullptr;
        j["outcome_search"] = {{"note", v.outcome_note}};
    }
    j["other_measurements"] = other_measurements_json(v.others);
    j["diagnostics"] = nlohmann::ordered_json::array();
    for (const auto& d : a.diagnostics) {
        nlohmann::ordered_json bins = nlohmann::ordered_json::array();
        for (const auto& b : d.bins) bins.push_back({{"bin", b.label}, {"x", b.x}, {"n", b.n}, {"factor", b.factor}, {"low", b.low}, {"high", b.high}});
        j["diagnostics"].push_back({{"covariate", d.covariate},
                                    {"kind", d.numeric ? "numeric" : "categorical"},
                                    {"strength", d.strength},
                                    {"best_shape", d.best_shape},
                                    {"p_value", d.p_value},
                                    {"p_adjusted", d.p_adjusted},
                                    {"p_given_model", d.p_given_model},
                                    {"cause", d.cause},
                                    {"blank_cells", d.blank},
                                    {"bins", bins}});
        if (d.blank > 0 && d.numeric) j["diagnostics"].back()["blank_cells_taken_as"] = d.blank_value;
    }
    j["interactions"] = nlohmann::ordered_json::array();
    for (const auto& i : a.interactions) {
        j["interactions"].push_back({{"covariate", i.covariate}, {"times", i.times}, {"p_value", i.p_value}, {"kept", i.kept}, {"coefficient", i.coefficient}});
    }
    j["suspected_rows"] = nlohmann::ordered_json::array();
    for (const auto& r : a.suspected) {
        j["suspected_rows"].push_back({{"line", v.data.trials[r.row].line},
                                       {"flower_id", v.data.trials[r.row].flower_id},
                                       {"measured_gf", r.measured_gf},
                                       {"model_gf", r.expected_gf},
                                       {"robust_z", r.z}});
    }
    j["constant_columns"] = v.input.covariates.constant;
    j["screened_columns"] = nlohmann::ordered_json::array();
    for (const auto& c : a.screened) {
        j["screened_columns"].push_back({{"covariate", c.covariate},
                                         {"levels", c.levels},
                                         {"flowers_per_level", c.flowers_per_level},
                                         {"between_level_share", c.between_level_share},
                                         {"chance_share", c.chance_share},
                                         {"reason", c.reason}});
    }
    // A file of several species: each one's rows with the shared extension, and its own search when that was worse for one.
    j["per_species"] = v.per_species;
    j["by_species"] = nlohmann::ordered_json::array();
    for (const auto& c : v.by_species) {
        nlohmann::ordered_json e = {{"species", c.species}, {"rows", c.rows}, {"baseline_rmse_gf", c.baseline_rmse_gf},
                                    {"shared_cv_rmse_gf", c.shared_cv_rmse_gf}, {"own", nullptr}};
        if (c.own) {
            nlohmann::ordered_json causes = nlohmann::ordered_json::array();
            for (const auto& cause : c.own->causes) {
                causes.push_back({{"covariate", cause.covariate}, {"direction", cause.direction}, {"effect_size", cause.effect_size}, {"p_value", cause.p_value}});
            }
            e["own"] = {{"discrepancy_found", c.own->discrepancy_found}, {"causes", causes}, {"cv_rmse_gf", c.own->extended_cv_rmse_gf}, {"gain", c.own->gain}};
        }
        e["extended_species_written"] = !c.extended_species_json.empty();
        j["by_species"].push_back(e);
    }
    // The search ran on a sample of flowers (long data): how large, and every row's check of the columns it left out.
    j["search_sample"] = nullptr;
    if (a.sample) {
        nlohmann::ordered_json left_out = nlohmann::ordered_json::array();
        for (std::size_t k = 0; k < a.sample->columns.size(); ++k) left_out.push_back({{"covariate", a.sample->columns[k]}, {"z", a.sample->z[k]}});
        j["search_sample"] = {{"rows", a.sample->rows}, {"flowers", a.sample->flowers}, {"z_needed", a.sample->z_needed}, {"left_out", left_out}};
    }
    j["options"] = {{"permutations", options.permutations}, {"alpha", options.alpha}, {"seed", options.seed}, {"folds", a.folds},
                    {"bootstrap", options.bootstrap}, {"search_rows", options.search_rows}};
    j["log"] = a.log;
    return assets::json_text(j, 2) + "\n";
}

// The findings in words a plant-biomechanics reader needs no statistics glossary for: how far the
// simulation is off, what it misses and by how much, and how much better the extended model predicts
// trials it was not fitted to. The technical lines follow it.
std::string in_short(const ValidationResult& v) {
    const AnalysisResult& a = v.analysis;
    std::ostringstream o;
    o << "in short:  ";
    const bool wrong_falls = v.outcome_search && v.outcome_search->analysis.discrepancy_found;
    const char* falls = " Its falls do not agree: see the outcome: lines.\n";
    if (!a.discrepancy_found) {
        o << (wrong_falls ? "the measured forces agree with the simulation: no column and no overall scale departs from it by more than chance would."
                          : "the measurements agree with the simulation: nothing in the data (no column, no overall scale) departs from it by more "
                            "than chance would.")
          << (wrong_falls ? falls : "\n");
        return o.str();
    }
    const double f = a.calibration.factor;
    if (a.calibration.significant) {
        o << "the measured forces are " << fmt("%.2f", f) << " times what the simulation gives (likely between " << fmt("%.2f", a.calibration.low)
          << " and " << fmt("%.2f", a.calibration.high) << " times)";
    } else {
        o << "on average the simulation's forces are of the measured size";
    }
    for (std::size_t k = 0; k < a.causes.size(); ++k) {
        const Cause& c = a.causes[k];
        o << (k == 0 ? (a.calibration.significant ? ". Beyond that, the measured force " : ", but the measured force ") : "; and it ");
        const std::string size = fmt("%.0f %%", 100 * std::abs(c.effect_size));
        if (c.shape.form == "category") {
            o << "is " << size << (c.effect_size >= 0 ? " higher" : " lower") << " relative to the simulation where " << c.covariate << " = " << c.category
              << " than at its other values";
        } else if (c.shape.form == "peaked") {
            o << "relative to the simulation is " << (c.effect_size < 0 ? "highest" : "lowest") << " at " << c.covariate << " = "
              << fmt("%.4g", c.shape.origin) << ", " << size << (c.effect_size < 0 ? " lower" : " higher") << " toward the ends of its range";
        } else {
            o << (c.effect_size >= 0 ? "rises" : "falls") << " by " << size << " relative to the simulation "
              << (c.covariate == "insertion" ? cause_span(c) : "as " + c.covariate + " goes " + cause_span(c));
        }
    }
    o << ". With " << (a.causes.empty() ? "that correction" : "these corrections") << " the simulation's typical error on trials it was not fitted to falls from "
      << fmt("%.0f", a.baseline_cv_rmse_gf) << " to " << fmt("%.0f", a.extended_cv_rmse_gf) << " gf (" << fmt("%.0f %%", 100 * a.gain) << " less)."
      << (wrong_falls ? falls : "\n");
    return o.str();
}

namespace {

// A search on a sample of flowers, and what every row says of the columns it left out.
std::string sample_words(const AnalysisResult& a) {
    const SearchSample& s = *a.sample;
    std::ostringstream o;
    o << "the search for causes ran on a random " << s.flowers << " of " << a.n_flowers << " flowers (" << s.rows << " of " << a.n_trials
      << " rows); the model, its intervals and its gain are fitted on every row. ";
    std::vector<std::size_t> missed;
    std::size_t largest = 0;
    for (std::size_t k = 0; k < s.columns.size(); ++k) {
        if (s.z[k] > s.z_needed) missed.push_back(k);
        if (s.z[k] > s.z[largest]) largest = k;
    }
    if (s.columns.empty()) {
        o << "Every column is in the model.";
    } else if (missed.empty()) {
        o << "On every row, no column left out of the model shows a trend against it: the largest is " << s.columns[largest] << " at |z| "
          << fmt("%.1f", s.z[largest]) << ", " << fmt("%.1f", s.z_needed) << " needed (flower-clustered errors, a line and a curve each)";
    } else {
        for (std::size_t k = 0; k < missed.size(); ++k) {
            o << (k ? ", " : "") << s.columns[missed[k]] << " (|z| " << fmt("%.1f", s.z[missed[k]]) << ")";
        }
        o << (missed.size() == 1 ? " shows" : " show") << " a trend on every row that the sample did not find (" << fmt("%.1f", s.z_needed)
          << " needed, flower-clustered errors): an effect too small for the sample; run again with a larger --search-rows";
    }
    return o.str();
}

} // namespace

// The `outcome:` block: what the simulation gets wrong about standing and falling, and how much a
// correction by the columns found would help on rows it was not fitted to.
std::string outcome_block(const ValidationResult& v) {
    if (!v.baseline_outcome) return {};
    if (!v.outcome_search) return "outcome:   " + v.outcome_note + "\n";
    const OutcomeSearch& s = *v.outcome_search;
    const AnalysisResult& a = s.analysis;
    std::ostringstream o;
    o << "outcome:   " << s.rows.size() << " rows stood or fell, " << a.n_flowers << " flowers; every column against fell minus the simulated chance of falling\n";
    if (!a.discrepancy_found) {
        o << "  no column explains the wrong falls beyond chance after correction\n";
        return o.str();
    }
    if (a.calibration.significant) {
        const double level = 100 * std::log(a.calibration.factor);
        o << "  level:   the flowers fall " << fmt("%.1f", std::abs(level)) << " points of chance " << (level >= 0 ? "more" : "less")
          << " often than simulated, whatever the columns\n";
    }
    for (std::size_t k = 0; k < s.causes.size(); ++k) {
        const OutcomeCause& c = s.causes[k];
        o << "  cause " << k + 1 << ": " << c.covariate << (c.category.empty() ? "" : " = " + c.category) << ", " << c.direction << ", " << c.shape
          << ", the chance of falling " << fmt("%+.2f", c.effect) << " [" << fmt("%+.2f", c.effect_low) << ", " << fmt("%+.2f", c.effect_high) << "]";
        if (c.category.empty()) o << " from " << fmt("%.4g", c.x_low) << " to " << fmt("%.4g", c.x_high);
        o << ", p = " << fmt("%.3g", c.p_value) << "\n";
    }
    o << "  held out: log-loss " << fmt("%.3f", s.baseline.log_loss) << " -> " << fmt("%.3f", s.held_out.log_loss) << ", Brier " << fmt("%.3f", s.baseline.brier)
      << " -> " << fmt("%.3f", s.held_out.brier) << ", accuracy " << fmt("%.0f %%", 100 * s.baseline.accuracy) << " -> " << fmt("%.0f %%", 100 * s.held_out.accuracy)
      << " (coefficients fitted without the row's fold)\n";
    if (!s.hold_terms.empty()) {
        o << "  holding: " << s.hold_terms.size() << " term(s) on what holds a stem at rest (\"applies_to\": \"hold\"), fitted to the falls (log-loss "
          << fmt("%.3f", s.hold_fit_log_loss) << ")";
        const bool unchecked = s.hold_rejected && !s.hold_note.empty();
        const OutcomeScores* through = unchecked ? nullptr : s.hold_rejected ? &s.hold_simulated : (v.extended_outcome ? &*v.extended_outcome : nullptr);
        if (v.baseline_outcome && through) {
            o << "; the species with it through the simulation: log-loss " << fmt("%.3f", v.baseline_outcome->log_loss) << " -> "
              << fmt("%.3f", through->log_loss) << ", Brier " << fmt("%.3f", v.baseline_outcome->brier) << " -> " << fmt("%.3f", through->brier)
              << ", accuracy " << fmt("%.0f %%", 100 * v.baseline_outcome->accuracy) << " -> " << fmt("%.0f %%", 100 * through->accuracy);
            if (s.hold_rejected) o << ": worse, so it is left out of the species written";
        } else {
            o << "; " << (unchecked ? s.hold_note : "not run through the simulation");
        }
        o << "\n";
    } else if (!s.hold_note.empty()) {
        o << "  holding: " << s.hold_note << "\n";
    } else if (s.hold_fitted) {
        o << "  holding: no term on the holding moves these falls (each row's chance simulated at holdings of 0.5 to 2)\n";
    }
    return o.str();
}

std::string validation_summary(const ValidationResult& v) {
    const AnalysisResult& a = v.analysis;
    std::ostringstream o;
    o << v.measured_file << ": " << a.n_trials << " trials, " << a.n_flowers << " flower(s), species " << (v.species.empty() ? "(several)" : v.species)
      << "\n";
    o << in_short(v);
    if (a.sample) o << "sample:    " << sample_words(a) << "\n";
    for (const auto& c : a.screened) {
        o << "screened:  " << c.covariate << " (" << c.levels << " levels, " << fmt("%.1f", c.flowers_per_level)
          << " flowers a level): not tested level by level; " << fmt("%.1f %%", 100 * c.between_level_share) << " of the residual's variance lies between its levels, "
          << fmt("%.1f %%", 100 * c.chance_share) << " by chance\n";
    }
    if (!a.suspected.empty()) {
        o << "set aside: " << a.suspected.size() << " row(s) as suspected gross errors (a slipped gauge, a misread scale), far from every "
          << "other row against the model; the figures below are on the other " << a.n_trials - a.suspected.size() << ":";
        for (std::size_t k = 0; k < a.suspected.size() && k < 8; ++k) {
            const auto& r = a.suspected[k];
            o << (k ? "," : "") << " line " << v.data.trials[r.row].line << " (" << fmt("%.0f", r.measured_gf) << " gf, the model " << fmt("%.0f", r.expected_gf)
              << ")";
        }
        if (a.suspected.size() > 8) o << " and " << a.suspected.size() - 8 << " more (the JSON's suspected_rows)";
        o << "\n";
    }
    for (const auto& d : a.diagnostics) {
        if (d.blank == 0) continue;
        o << "blank:     " << d.covariate << " is empty in " << d.blank << " of " << a.n_trials << " rows: "
          << (d.numeric ? "those rows take the middle of its range, " + fmt("%.4g", d.blank_value) : std::string("those rows are a level of their own, \"(missing)\""))
          << "\n";
    }
    o << "baseline:  RMSE " << fmt("%.1f", a.baseline_rmse_gf) << " gf, CV RMSE " << fmt("%.1f", a.baseline_cv_rmse_gf) << " gf";
    if (v.baseline_outcome) o << outcome_words(*v.baseline_outcome);
    o << "\n";
    if (v.spread) {
        o << "flowers:   differ by themselves by " << fmt("%.1f %%", 100.0 * (std::exp(v.spread->sd_log) - 1.0))
          << " (a flower effect's standard deviation, after the model; each row scatters " << fmt("%.1f %%", 100.0 * (std::exp(v.spread->within_sd_log) - 1.0))
          << " about its flower's mean; " << v.spread->flowers << " flowers of 2 rows or more)\n";
    }
    o << outcome_block(v);
    if (!a.discrepancy_found) {
        o << "no discrepancy found" << (v.outcome_search ? " in the forces" : "") << ": no covariate and no overall level is significant after correction\n";
        if (!v.resimulation_note.empty()) o << "note: " << v.resimulation_note << "\n";
        for (const auto& m : v.others) o << (m.worse ? "WORSE:     " : "also:      ") << other_measure_words(m) << "\n";
        return o.str();
    }
    o << "level:     measured/simulated x" << fmt("%.3f", a.calibration.factor) << " [" << fmt("%.3f", a.calibration.low) << ", "
      << fmt("%.3f", a.calibration.high) << "], p = " << fmt("%.3g", a.calibration.p_value) << (a.calibration.significant ? "" : " (not significant alone)")
      << "\n";
    for (std::size_t k = 0; k < a.causes.size(); ++k) {
        const Cause& c = a.causes[k];
        o << "cause " << k + 1 << ":   " << c.covariate << (c.category.empty() ? "" : " = " + c.category) << ", " << c.direction << ", "
          << c.shape.form << ", effect " << fmt("%+.1f %%", 100 * c.effect_size) << " [" << fmt("%+.1f", 100 * c.effect_low) << ", "
          << fmt("%+.1f", 100 * c.effect_high) << "], p = " << fmt("%.3g", c.p_value) << "\n";
    }
    for (const auto& i : a.interactions) {
        if (!i.kept) continue;
        o << "together:  " << i.covariate << "'s effect changes with " << i.times << " (an interaction term), p = " << fmt("%.3g", i.p_value) << "\n";
    }
    if (!a.interactions.empty() && std::none_of(a.interactions.begin(), a.interactions.end(), [](const InteractionCheck& i) { return i.kept; })) {
        o << "together:  no cause's effect changes with another column beyond chance (" << a.interactions.size() << " pairs checked)\n";
    }
    o << "extended:  CV RMSE " << fmt("%.1f", a.extended_cv_rmse_gf) << " gf, gain " << fmt("%.1f %%", 100 * a.gain);
    if (v.simulated_extended_rmse_gf) o << "; the extended species simulated: RMSE " << fmt("%.1f", *v.simulated_extended_rmse_gf) << " gf";
    if (v.extended_outcome) o << outcome_words(*v.extended_outcome);
    o << "\n";
    if (!v.resimulation_note.empty()) o << "note: " << v.resimulation_note << "\n";
    for (const auto& m : v.others) o << (m.worse ? "WORSE:     " : "also:      ") << other_measure_words(m) << "\n";
    if (v.per_species) {
        o << "again:     the extension found on every species' rows is worse for one, so each species was searched on its own rows:\n";
        for (const auto& c : v.by_species) {
            o << "  " << c.species << " (" << c.rows << " rows): ";
            if (!c.own) {
                o << "too few rows to search\n";
                continue;
            }
            if (c.own->causes.empty()) o << (c.own->discrepancy_found ? "an overall level only" : "nothing beyond chance");
            for (std::size_t k = 0; k < c.own->causes.size(); ++k) {
                const Cause& cause = c.own->causes[k];
                o << (k ? ", " : "") << cause.covariate << " " << cause.direction << " " << fmt("%+.1f %%", 100 * cause.effect_size);
            }
            o << "; held-out error " << fmt("%.1f", c.own->baseline_cv_rmse_gf) << " -> " << fmt("%.1f", c.own->discrepancy_found ? c.own->extended_cv_rmse_gf : c.own->baseline_cv_rmse_gf)
              << " gf\n";
        }
    }
    return o.str();
}

Result<void> write_validation_report(const ValidationResult& v, const AnalysisOptions& options, const std::filesystem::path& dir,
                                     const std::string& extra_markdown) {
    assets::OutputBatch batch;
    if (auto folder = batch.folder(dir); !folder) return folder;
    for (const auto& [name, text] : validation_report_files(v, options, extra_markdown)) {
        if (auto staged = batch.add(dir / name, text); !staged) return staged;
    }
    return batch.commit();
}

std::vector<std::pair<std::string, std::string>> validation_report_files(const ValidationResult& v, const AnalysisOptions& options, const std::string& extra_markdown) {
    const AnalysisResult& a = v.analysis;
    std::ostringstream md;
    md << "# Measured insertions against the simulation\n\n";
    md << "Data: `" << v.measured_file << "`, " << a.n_trials << " trials of " << a.n_flowers << " flower(s); species `"
       << (v.species.empty() ? "several" : v.species) << "`. Generated by `ikebana validate` (" << options.permutations
       << " permutations, family-wise alpha " << options.alpha << ", seed " << options.seed << ").\n\n";
    if (a.rows_as_groups) {
        md << "> Fewer than 4 flowers: rows stand in for flowers in the permutations, the folds and the bootstrap. With one row per "
              "insertion count (published means) this treats the rows as independent, which they are not quite.\n\n";
    }
    {
        // Verbatim in a fence, where HTML is not read; a fence in the data would end it early.
        std::string summary = terminal_text(validation_summary(v));
        for (std::size_t at = summary.find("```"); at != std::string::npos; at = summary.find("```", at)) summary.replace(at, 3, "'''");
        md << "## Summary\n\n```\n" << summary << "```\n\n";
    }
    if (!a.suspected.empty()) {
        md << "## Rows set aside\n\nThese rows lie more than " << fmt("%.0f", options.outlier_z)
           << " robust standard deviations (1.4826 × the median absolute deviation) from the median of all rows, against the fitted model: a "
              "slipped gauge or a misread scale looks like this. The analysis ran without them; check them against the lab notes.\n\n"
              "| line | flower | measured (gf) | the model (gf) | robust z |\n|---|---|---|---|---|\n";
        for (const auto& r : a.suspected) {
            md << "| " << v.data.trials[r.row].line << " | " << cell(v.data.trials[r.row].flower_id) << " | " << fmt("%.1f", r.measured_gf) << " | "
               << fmt("%.1f", r.expected_gf) << " | " << fmt("%.1f", r.z) << " |\n";
        }
        md << "\n";
    }
    md << "![simulation against measurement](model_vs_data.svg)\n\n";
    md << "## How the simulation was compared\n\n"
          "Every trial was run through the live insertion and deterioration systems (`ikebana predict`). The residual is "
          "ln(measured / simulated): forces are positive and their errors multiplicative. Errors in gram-force are the RMSE of "
          "measured minus simulated; the cross-validated RMSE holds out whole flowers (" << a.folds << " folds). The baseline fits "
          "nothing, so its CV RMSE equals its RMSE.\n\n";
    md << "## What the simulation gets wrong\n\n";
    md << "Every candidate column against the residual. *strength*: the share of the residual's variance the best single shape "
          "explains; *p*: permutation test keeping each flower's rows together; *family*: corrected for testing every column "
          "(Westfall–Young step-down maxT, the permutation form of Holm's method); "
          "*given model*: the same test against the final model's residual (a column that only mirrors a cause loses "
          "significance here).\n\n";
    md << "| column | kind | blank cells | best shape | strength | p | family | given model | cause |\n|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& d : a.diagnostics) {
        md << "| `" << cell(d.covariate) << "` | " << (d.numeric ? "numeric" : "categorical") << " | "
           << (d.blank == 0 ? std::string("0") : std::to_string(d.blank) + (d.numeric ? " (taken as " + fmt("%.4g", d.blank_value) + ")" : " (a level)")) << " | "
           << d.best_shape << " | " << fmt("%.3f", d.strength)
           << " | " << fmt("%.3g", d.p_value) << " | " << fmt("%.3g", d.p_adjusted) << " | " << fmt("%.3g", d.p_given_model) << " | "
           << (d.cause ? "**yes**" : "") << " |\n";
    }
    if (!v.input.covariates.constant.empty()) {
        md << "\nNot tested (one value only):";
        for (const auto& c : v.input.covariates.constant) md << " `" << cell(c) << "`";
        md << ".\n";
    }
    if (!a.screened.empty()) {
        md << "\nScreened out, not tested level by level (too many levels for the flowers that carry them). As a random "
              "effect would be summarised: the share of the residual's variance between its levels' means, beside the "
              "share chance alone gives that many levels.\n\n| column | levels | flowers a level | between levels | by chance | why |\n"
              "|---|---|---|---|---|---|\n";
        for (const auto& c : a.screened) {
            md << "| `" << cell(c.covariate) << "` | " << c.levels << " | " << fmt("%.1f", c.flowers_per_level) << " | " << fmt("%.1f %%", 100 * c.between_level_share)
               << " | " << fmt("%.1f %%", 100 * c.chance_share) << " | " << c.reason << " |\n";
        }
    }
    md << "\n";
    std::vector<std::pair<std::string, std::string>> figures;
    figures.emplace_back("model_vs_data.svg", model_chart(v));
    if (!v.baseline_fall_probability.empty() && v.baseline_outcome) {
        figures.emplace_back("calibration.svg", calibration_chart(v));
        md << "## Outcomes: the chance of falling against what fell\n\n![calibration](calibration.svg)\n\n"
           << "| predicted chance | rows | baseline: mean chance | share that fell | ±2 s.e. |\n|---|---|---|---|---|\n";
        for (const auto& b : calibration_bins(v.data, v.baseline_fall_probability)) {
            md << "| " << fmt("%.1f", b.low) << "–" << fmt("%.1f", b.high) << " | " << b.rows << " | " << fmt("%.3f", b.predicted) << " | "
               << fmt("%.3f", b.fell) << " | " << fmt("%.3f", 2.0 * b.se) << " |\n";
        }
        md << "\nA calibrated model's bins lie on the diagonal. The simulation's chance is the share of its mixture (16 placements, "
              "sound and split ends) that fell; a bin far from the diagonal is where it is wrong about standing and falling.\n\n";
        md << outcome_markdown(v, figures);
    }
    for (const auto& d : a.diagnostics) {
        if (!flagged(d, options.alpha)) continue;
        const std::string name = "residual_" + file_safe(d.covariate) + ".svg";
        figures.emplace_back(name, residual_chart(v, d));
        md << "### `" << cell(d.covariate) << "`\n\n![residual against " << cell(d.covariate) << "](" << name << ")\n\n";
        md << "| bin | n | measured / simulated | ±2 s.e. |\n|---|---|---|---|\n";
        for (const auto& b : d.bins) {
            md << "| " << cell(b.label) << " | " << b.n << " | " << fmt("%.3f", b.factor) << " | "
               << (b.n > 1 ? fmt("%.3f", b.low) + "–" + fmt("%.3f", b.high) : std::string("— (one trial)")) << " |\n";
        }
        md << "\n";
    }
    md << "## Causes\n\n";
    if (a.causes.empty()) md << "No column explains the residual beyond chance after correction.\n\n";
    for (std::size_t k = 0; k < a.causes.size(); ++k) md << k + 1 << ". **`" << cell(a.causes[k].covariate) << "`** — " << prose(v.explanations[k]) << "\n";
    md << "\nOverall level: the extended model multiplies the simulation by " << fmt("%.3f", a.calibration.factor) << " on average (95 % interval "
       << fmt("%.3f", a.calibration.low) << "–" << fmt("%.3f", a.calibration.high) << "); the baseline's level alone has p = "
       << fmt("%.3g", a.calibration.p_value) << " (sign flips of whole flowers).\n\n";
    md << "## The extension\n\n";
    if (a.extension.empty()) {
        md << "None: nothing was found, so the species is unchanged and the gain is 0.\n\n";
    } else {
        md << "The force the species gives is multiplied by exp(sum of terms):\n\n| covariate | form | coefficient | scale | origin | category |\n|---|---|---|---|---|---|\n";
        for (const auto& t : a.extension) {
            md << "| `" << cell(t.covariate) << "` | " << t.form << " | " << fmt("%.5g", t.coefficient) << " | " << fmt("%.5g", t.scale) << " | "
               << fmt("%.5g", t.origin) << " | " << cell(t.category) << " |\n";
        }
        md << "\n`--write-species` writes these into a species file that `ikebana predict --species`, `ikebana experiment --species` and the app "
              "load like any other.\n\n";
    }
    md << "## Gain\n\n| | baseline | extended |\n|---|---|---|\n";
    md << "| RMSE (gf) | " << fmt("%.1f", a.baseline_rmse_gf) << " | " << fmt("%.1f", a.extended_rmse_gf) << " |\n";
    md << "| grouped CV RMSE (gf) | " << fmt("%.1f", a.baseline_cv_rmse_gf) << " | " << fmt("%.1f", a.extended_cv_rmse_gf) << " |\n";
    md << "| RMSE of ln(measured/simulated) | " << fmt("%.4f", a.baseline_log_rmse) << " | " << fmt("%.4f", a.extended_log_rmse) << " |\n";
    if (v.simulated_extended_rmse_gf) md << "| RMSE, extended species through the simulation (gf) | " << fmt("%.1f", a.baseline_rmse_gf) << " | " << fmt("%.1f", *v.simulated_extended_rmse_gf) << " |\n";
    if (v.baseline_outcome) {
        const auto& b = *v.baseline_outcome;
        const auto& e = v.extended_outcome;
        const std::string rows = std::to_string(b.rows) + " rows stood/fell";
        md << "| outcome accuracy (" << rows << ") | " << fmt("%.1f %%", 100 * b.accuracy) << " | "
           << (e ? fmt("%.1f %%", 100 * e->accuracy) : std::string("not simulated")) << " |\n";
        md << "| Brier score of the chance of falling (0 perfect, 0.25 a coin) | " << fmt("%.3f", b.brier) << " | "
           << (e ? fmt("%.3f", e->brier) : std::string("not simulated")) << " |\n";
        md << "| log-loss of the chance of falling (0.693 a coin) | " << fmt("%.3f", b.log_loss) << " | "
           << (e ? fmt("%.3f", e->log_loss) : std::string("not simulated")) << " |\n";
    }
    md << "\nGain = 1 − extended CV RMSE / baseline CV RMSE = **" << fmt("%.1f %%", 100 * a.gain) << "**.\n\n";
    if (!v.resimulation_note.empty()) md << "Note: " << v.resimulation_note << ".\n\n";
    if (!v.others.empty()) {
        md << "## Every other measurement, before and after\n\nAn extension fitted to the forces must not move what else was measured away from "
              "its measurement.\n\n| measured quantity | measured | baseline | extended | verdict |\n|---|---|---|---|---|\n";
        for (const auto& m : v.others) {
            md << "| " << cell(m.name) << " | " << fmt("%.3g", m.measured) << " | " << fmt("%.3g", m.baseline) << " | " << fmt("%.3g", m.extended) << " | "
               << (m.worse ? "**clearly worse**" : "not worse") << " |\n";
        }
        md << "\n";
    }
    md << extra_markdown;
    md << "## Decisions, step by step\n\n";
    for (const auto& line : a.log) md << "- " << line << "\n";
    figures.emplace_back("report.md", md.str());
    return figures;
}

} // namespace ikebana::game
