#include "game/cli/validate_command.hpp"

#include "engine/core/utf8.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/analysis/validation_report.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/option_checks.hpp"
#include "game/experiment/insertion_experiment.hpp"
#include "game/species/species.hpp"

namespace ikebana::game {

namespace {

// A species' id is its file's name (`species check` holds every file to that): the extended species
// written to ext.json is "ext", whatever the species it extends was called.
std::string species_named_as_file(const std::string& json, const std::filesystem::path& path) {
    auto root = nlohmann::ordered_json::parse(json, nullptr, false);
    if (root.is_discarded() || !root.is_object()) return json;
    root["id"] = path.stem().string();
    return assets::json_text(root, 2) + "\n";
}


struct Args {
    std::string measured;
    std::string species;
    std::string json;
    std::string report;
    std::string write_species;
    std::vector<std::string> ignore;
    bool paper = false;
    bool alpha_given = false;
    std::uint32_t paper_trials = 15;
    std::uint32_t paper_hold_trials = 100;
    std::uint32_t memory_mb = 1024;
    AnalysisOptions analysis;
};

struct PaperExperiment {
    double break_mean = 0.0, fall_mean = 0.0;
    double extended_break_mean = 0.0, extended_fall_mean = 0.0;
    std::uint32_t never_fell = 0, extended_never_fell = 0, max_insertions = 0;
};

// The paper's experiment (2.6 insertions to break, 5.8 to fall) with the baseline and the extended species.
Result<PaperExperiment> run_paper_experiment(const std::string& extended_species, std::uint32_t trials, bool tty) {
    PaperExperiment out;
    ExperimentOptions options;
    options.trials = trials;
    auto progress = [tty](const char* which) {
        return [tty, which](std::uint32_t t, std::uint32_t n) {
            if (tty) std::fprintf(stderr, "\r\033[Kexperiment (%s): trial %u / %u", which, t, n);
        };
    };
    auto baseline = run_insertion_experiment(options, progress("baseline"));
    if (!baseline) return std::move(baseline).error();
    out.break_mean = baseline->mean_insertions_to_break;
    out.fall_mean = baseline->mean_insertions_to_fall;
    out.never_fell = baseline->trials_never_fell;
    out.max_insertions = options.max_insertions;
    options.species = extended_species;
    auto extended = run_insertion_experiment(options, progress("extended"));
    if (!extended) return std::move(extended).error();
    out.extended_break_mean = extended->mean_insertions_to_break;
    out.extended_fall_mean = extended->mean_insertions_to_fall;
    out.extended_never_fell = extended->trials_never_fell;
    if (tty) std::fprintf(stderr, "\r\033[K");
    return out;
}

// The paper's falls as a measured outcome (issue 57). What holds a stem at rest is the part of the model
// the forces cannot see (a gauge reads them while the stem slides in), so it is fitted to the falls: a
// level on the holding alone ("applies_to": "hold"), found by bisection so that the experiment's mean
// insertions until the fall is the paper's 5.8, over `trials` flowers (the expectation, not fifteen
// draws of it: a 15-flower mean has a standard error near 0.8 insertions).
constexpr double paper_insertions_to_fall = 5.8;

struct HoldFit {
    double coefficient = 0.0; // ln of the hold factor
    double fall_mean = 0.0;   // over `trials` flowers, with it
    double fall_mean_before = 0.0;
    std::uint32_t trials = 0;
    std::uint32_t runs = 0;
    std::string species_json;
};

Result<std::string> with_hold_level(const std::string& species_json, double coefficient) {
    auto j = nlohmann::ordered_json::parse(species_json, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("deterioration")) return make_error(ErrorCode::parse_error, "the extended species is not a species");
    auto& terms = j["deterioration"]["terms"];
    if (!terms.is_array()) terms = nlohmann::ordered_json::array();
    terms.push_back({{"covariate", "insertion"}, {"form", "constant"}, {"coefficient", coefficient}, {"applies_to", "hold"}});
    return assets::json_text(j, 2) + "\n";
}

Result<double> mean_insertions_to_fall(const std::string& species_json, std::uint32_t trials, const ExperimentProgress& progress) {
    const auto file = (std::filesystem::temp_directory_path() / ("ikebana-hold-fit-" + std::to_string(getpid()) + ".json")).string();
    if (auto w = assets::write_text_file(file, species_json); !w) return std::move(w).error();
    ExperimentOptions options;
    options.trials = trials;
    options.species = file;
    auto result = run_insertion_experiment(options, progress);
    std::filesystem::remove(file);
    if (!result) return std::move(result).error();
    return result->mean_insertions_to_fall;
}

Result<HoldFit> fit_hold_level(const std::string& species_json, std::uint32_t trials, bool tty) {
    HoldFit fit;
    fit.trials = trials;
    const auto falls_with = [&](double coefficient) -> Result<double> {
        auto species = with_hold_level(species_json, coefficient);
        if (!species) return std::move(species).error();
        ++fit.runs;
        const auto run = fit.runs;
        return mean_insertions_to_fall(*species, trials, [tty, run](std::uint32_t t, std::uint32_t n) {
            if (tty) std::fprintf(stderr, "\r\033[Kfitting the holding to the paper's falls: run %u, flower %u / %u", run, t, n);
        });
    };
    auto at_zero = falls_with(0.0);
    if (!at_zero) return std::move(at_zero).error();
    fit.fall_mean_before = *at_zero;
    // More holding, later falls: the bracket is [ln 0.6, 0] when they fall too late, [0, ln 1.35] when too early.
    double lo = *at_zero > paper_insertions_to_fall ? std::log(0.6) : 0.0;
    double hi = *at_zero > paper_insertions_to_fall ? 0.0 : std::log(1.35);
    double best = 0.0, best_mean = *at_zero;
    for (int step = 0; step < 12 && std::abs(best_mean - paper_insertions_to_fall) > 0.05; ++step) {
        const double mid = 0.5 * (lo + hi);
        auto mean = falls_with(mid);
        if (!mean) return std::move(mean).error();
        if (std::abs(*mean - paper_insertions_to_fall) < std::abs(best_mean - paper_insertions_to_fall)) {
            best = mid;
            best_mean = *mean;
        }
        (*mean > paper_insertions_to_fall ? hi : lo) = mid;
    }
    if (tty) std::fprintf(stderr, "\r\033[K");
    fit.coefficient = best;
    fit.fall_mean = best_mean;
    auto species = with_hold_level(species_json, best);
    if (!species) return std::move(species).error();
    fit.species_json = std::move(species).value();
    return fit;
}

// The paper's own model as a species: the shipped sunflower without the split-bottom factor the
// simulation adds on top of Table 2 (the paper's model is the table alone).
Result<std::string> papers_own_model_species() {
    auto text = assets::read_text_file(asset_path("species/sunflower.json"));
    if (!text) return std::move(text).error();
    auto j = nlohmann::ordered_json::parse(*text, nullptr, false);
    if (j.is_discarded()) return make_error(ErrorCode::parse_error, "species/sunflower.json: not JSON");
    j["id"] = "sunflower-papers-model";
    j["breakage"] = {{"model", "none"}};
    const auto path = (std::filesystem::temp_directory_path() / ("ikebana-papers-model-" + std::to_string(getpid()) + ".json")).string();
    if (auto w = assets::write_text_file(path, assets::json_text(j, 2)); !w) return std::move(w).error();
    return path;
}

int run_validate(Args& args) {
    const bool tty = isatty(fileno(stderr)) != 0;
    if (args.paper) {
        args.measured = (asset_dir() / "data" / "paper" / "table2_sunflower.csv").string();
        if (args.species.empty()) args.species = "sunflower";
        // Table 2's other two columns restate the measured force per pin and per mm: not covariates.
        args.ignore.insert(args.ignore.end(), {"max_per_pin_gf", "resistance_gf_per_mm"});
        // Six published means: sign flips of six rows cannot go below p = 1/32, so the family-wise
        // level for the paper's table is 0.05 unless --alpha says otherwise.
        if (!args.alpha_given) args.analysis.alpha = 0.05;
    }
    if (args.measured.empty()) {
        std::cerr << "ikebana validate: give MEASURED.csv, or --paper for the paper's data\n";
        return 2;
    }
    for (const auto& [option, path] : {std::pair{"--json", &args.json}, std::pair{"--write-species", &args.write_species}}) {
        if (path->empty()) continue;
        if (auto ok = assets::check_output_path(*path); !ok) {
            std::cerr << "ikebana validate: " << option << ": " << ok.error().message << "\n";
            return 2;
        }
    }
    // The species written is named as its file, and an id has lower-case letters, digits, '-' and '_':
    // a name that cannot be one is refused now, not after the search (`species check` refused EXT.json).
    if (!args.write_species.empty()) {
        const std::filesystem::path file(args.write_species);
        if (file.extension() != ".json" || !valid_species_id(file.stem().string())) {
            std::cerr << "ikebana validate: --write-species: " << terminal_text(args.write_species)
                      << ": a species file is named as its id, lower-case letters, digits, '-' or '_' before .json (ext.json, say)\n";
            return 2;
        }
    }
    // Every output is written at the end, all or none: a command that fails leaves nothing behind
    // (the report's folder, made here, goes again too).
    assets::OutputBatch outputs;
    if (!args.report.empty()) {
        if (auto ok = outputs.folder(args.report); !ok) {
            std::cerr << "ikebana validate: --report: " << ok.error().message << "\n";
            return 2;
        }
    }
    if (args.json.empty() && !args.paper && args.report.empty()) {
        std::cerr << "ikebana validate: --json OUT.json is required (or --report DIR)\n";
        return 2;
    }
    ValidationOptions options;
    options.species_override = args.species;
    options.ignore = args.ignore;
    options.analysis = args.analysis;
    options.analysis.memory_budget_bytes = std::size_t{args.memory_mb} << 20;
    options.analysis.progress = [tty](const std::string& stage, std::uint32_t done, std::uint32_t of) {
        if (tty) std::fprintf(stderr, "\r\033[K%s: %u / %u %s", stage.c_str(), done, of, stage == bootstrap_stage ? "flower resamples" : "permutations");
    };
    options.progress = [tty](const std::string& stage, std::size_t done, std::size_t of) {
        if (tty) std::fprintf(stderr, "\r\033[K%s: row %zu / %zu", stage.c_str(), done, of);
    };
    auto result = run_validation(args.measured, options);
    if (tty) std::fprintf(stderr, "\r\033[K");
    if (!result) {
        std::cerr << "ikebana validate: " << result.error().message << "\n";
        return 2;
    }
    ValidationResult& v = *result;
    // Column names and categories come from the file: shown, never sent to the terminal as controls.
    if (!v.data.table.note.empty()) std::printf("note: %s\n", terminal_text(v.data.table.note).c_str());
    std::printf("%s", terminal_text(validation_summary(v)).c_str());
    for (std::size_t k = 0; k < v.explanations.size(); ++k) std::printf("  %zu. %s\n", k + 1, terminal_text(v.explanations[k]).c_str());

    std::string json = validation_json(v, args.analysis);
    std::string extra = v.data.table.note.empty() ? std::string() : "Note on the input: " + v.data.table.note + ".\n\n";
    if (args.paper && !v.extended_species_json.empty()) {
        // The paper's experiment reads the extended species from a file of its own.
        const auto run_with = [&](const std::string& species_json) -> Result<PaperExperiment> {
            const auto species_file = (std::filesystem::temp_directory_path() / ("ikebana-paper-extended-" + std::to_string(getpid()) + ".json")).string();
            if (auto w = assets::write_text_file(species_file, species_json); !w) return std::move(w).error();
            auto experiment = run_paper_experiment(species_file, args.paper_trials, tty);
            std::filesystem::remove(species_file);
            return experiment;
        };
        // The experiment's means are measurements too: an extension that fits the forces and moves the
        // falls away from the paper's 5.8 is said to (within an insertion is not clearly worse).
        const auto judged = [](const PaperExperiment& e) {
            return std::vector<OtherMeasure>{
                judge_other_measure("insertions until the bottom breaks (the paper's experiment)", 2.6, e.break_mean, e.extended_break_mean, 1.0),
                judge_other_measure("insertions until the flower falls (the paper's experiment)", 5.8, e.fall_mean, e.extended_fall_mean, 1.0)};
        };
        const auto any_worse = [](const std::vector<OtherMeasure>& ms) { return std::any_of(ms.begin(), ms.end(), [](const OtherMeasure& m) { return m.worse; }); };
        const auto describe = [&](const PaperExperiment& e, const char* which) {
            char text[1024];
            std::snprintf(text, sizeof text,
                          "The paper's experiment (%u flowers at 45 degrees, again and again): the paper measured 2.6 insertions until the bottom "
                          "broke and 5.8 until the flower fell. Baseline species: %.1f and %.1f. Extended species%s: %.1f and %.1f "
                          "(%u of %u flowers still standing after %u insertions, counted as %u).\n",
                          args.paper_trials, e.break_mean, e.fall_mean, which, e.extended_break_mean, e.extended_fall_mean, e.extended_never_fell,
                          args.paper_trials, e.max_insertions, e.max_insertions + 1);
            return std::string(text);
        };
        auto experiment = run_with(v.extended_species_json);
        if (!experiment) {
            std::cerr << "ikebana validate: the paper's experiment: " << experiment.error().message << "\n";
            return 1;
        }
        std::string text = describe(*experiment, "");
        std::printf("%s", text.c_str());
        auto measures = judged(*experiment);
        for (const auto& m : measures) std::printf("%s%s\n", m.worse ? "WORSE: " : "also: ", other_measure_words(m).c_str());
        std::string applies_to = "push_and_hold";
        if (any_worse(measures)) {
            // Looked for again with that constraint: the forces are measured while the stem slides in;
            // the falls come from what holds it at rest. The same terms on the push alone fit the same
            // forces; if they leave the falls where the measurement is, that is the part of the model
            // that gives both.
            auto variant = extended_species_applied_to(v.extended_species_json, "push");
            auto again = variant ? run_with(*variant) : Result<PaperExperiment>(variant.error());
            if (!again) {
                std::cerr << "ikebana validate: the paper's experiment, the extension on the push alone: " << again.error().message << "\n";
                return 1;
            }
            const std::string second = describe(*again, " with the extension on the push alone");
            auto measures_again = judged(*again);
            const bool better = !any_worse(measures_again);
            const std::string verdict = better ? "Looked for again with the falls as a constraint: the extension applies to the push alone (the force a "
                                                 "gauge reads as the stem slides in); what holds a stem at rest stays the base model's. It keeps the "
                                                 "forces' fit and the falls; the species written is that one.\n"
                                               : "Looked for again with the falls as a constraint: the extension on the push alone is clearly worse too; "
                                                 "no part of the model found here gives both. The species written is the first, said to be worse.\n";
            std::printf("%s%s", second.c_str(), verdict.c_str());
            for (const auto& m : measures_again) std::printf("%s%s\n", m.worse ? "WORSE: " : "also: ", other_measure_words(m).c_str());
            text += "\n" + second + "\n" + verdict;
            if (better) {
                v.extended_species_json = *variant;
                experiment = std::move(again);
                measures = std::move(measures_again);
                applies_to = "push";
            }
        }
        // The falls as a measured outcome: the holding alone fitted to them (a level of 1 when the falls are
        // already the paper's).
        std::optional<HoldFit> hold;
        {
            auto fit = fit_hold_level(v.extended_species_json, args.paper_hold_trials, tty);
            if (!fit) {
                std::cerr << "ikebana validate: fitting the holding to the paper's falls: " << fit.error().message << "\n";
                return 1;
            }
            auto again = run_with(fit->species_json);
            if (!again) {
                std::cerr << "ikebana validate: the paper's experiment, with the holding fitted: " << again.error().message << "\n";
                return 1;
            }
            char said[1200];
            std::snprintf(said, sizeof said,
                          "The falls as a measured outcome: what holds a stem at rest is what the forces cannot see (a gauge reads them while "
                          "the stem slides in). A level on the holding alone (\"applies_to\": \"hold\"), fitted so that %u flowers fall after "
                          "the paper's 5.8 insertions on average, is x%.3f: the pins hold a stem at rest %.1f %% %s than they resist its push. "
                          "Over those %u flowers the mean insertions until the fall goes from %.2f to %.2f (%u runs of the experiment); the "
                          "forces are the push's and do not change. With it the paper's experiment (%u flowers): %.1f insertions until the "
                          "bottom breaks and %.1f until the flower falls (%u still standing after %u).\n",
                          fit->trials, std::exp(fit->coefficient), 100.0 * std::abs(1.0 - std::exp(fit->coefficient)),
                          fit->coefficient < 0.0 ? "less" : "more", fit->trials, fit->fall_mean_before, fit->fall_mean, fit->runs, args.paper_trials,
                          again->extended_break_mean, again->extended_fall_mean, again->extended_never_fell, again->max_insertions);
            std::printf("%s", said);
            text += "\n" + std::string(said);
            measures = judged(*again);
            for (const auto& m : measures) std::printf("%s%s\n", m.worse ? "WORSE: " : "also: ", other_measure_words(m).c_str());
            v.extended_species_json = fit->species_json;
            experiment = std::move(again);
            hold = std::move(fit).value();
        }
        v.others.insert(v.others.end(), measures.begin(), measures.end());
        extra += std::string("## The paper's experiment with the extended species\n\n") + text + "\n";
        auto j = nlohmann::ordered_json::parse(json);
        j["other_measurements"] = other_measurements_json(v.others);
        j["paper_experiment"] = {{"trials", args.paper_trials},
                                 {"measured", {{"insertions_to_break", 2.6}, {"insertions_to_fall", 5.8}}},
                                 {"baseline", {{"insertions_to_break", experiment->break_mean}, {"insertions_to_fall", experiment->fall_mean}}},
                                 {"extended", {{"insertions_to_break", experiment->extended_break_mean}, {"insertions_to_fall", experiment->extended_fall_mean},
                                               {"still_standing", experiment->extended_never_fell}, {"applies_to", applies_to}}}};
        if (hold) {
            j["paper_experiment"]["extended"]["hold_fit"] = {{"hold_factor", std::exp(hold->coefficient)},
                                                             {"coefficient", hold->coefficient},
                                                             {"trials", hold->trials},
                                                             {"insertions_to_fall_before", hold->fall_mean_before},
                                                             {"insertions_to_fall", hold->fall_mean},
                                                             {"runs", hold->runs}};
        }
        json = assets::json_text(j, 2) + "\n";
    }
    // Several species: a file for each that has an extension (FILE.<species>.json).
    std::vector<std::string> species_written;
    for (const auto& c : v.by_species) {
        if (c.extended_species_json.empty() || args.write_species.empty()) continue;
        std::string path = species_output_path(args.write_species, c.species);
        // Two ids that give one file name ("a b" and "a_b") are told apart by a number.
        for (int k = 2; std::find(species_written.begin(), species_written.end(), path) != species_written.end(); ++k) {
            path = species_output_path(args.write_species, c.species + "-" + std::to_string(k));
        }
        species_written.push_back(path);
        if (auto w = outputs.add(species_written.back(), species_named_as_file(c.extended_species_json, path)); !w) {
            std::cerr << "ikebana validate: " << w.error().message << "\n";
            return 1;
        }
    }
    if (!v.extended_species_json.empty() && !args.write_species.empty()) {
        if (auto w = outputs.add(args.write_species, species_named_as_file(v.extended_species_json, args.write_species)); !w) {
            std::cerr << "ikebana validate: " << w.error().message << "\n";
            return 1;
        }
    } else if (!args.write_species.empty() && species_written.empty()) {
        std::printf("nothing found: no extended species written (%s)\n", args.write_species.c_str());
    }
    if (args.paper) {
        // Table 2 against the paper's own model too: is "insertions 3-6 are experimental error"
        // something six published means can refute?
        auto model = papers_own_model_species();
        if (!model) {
            std::cerr << "ikebana validate: " << model.error().message << "\n";
            return 1;
        }
        ValidationOptions own = options;
        own.species_override = *model;
        own.resimulate_limit = 0;
        auto second = run_validation(args.measured, own);
        std::filesystem::remove(*model);
        if (tty) std::fprintf(stderr, "\r\033[K");
        if (!second) {
            std::cerr << "ikebana validate: the paper's own model: " << second.error().message << "\n";
            return 1;
        }
        const auto& d = second->analysis.diagnostics;
        const auto insertion = std::find_if(d.begin(), d.end(), [](const auto& x) { return x.covariate == "insertion"; });
        std::string bins;
        if (insertion != d.end()) {
            for (const auto& b : insertion->bins) bins += (bins.empty() ? "" : ", ") + b.label + ": " + std::to_string(b.factor).substr(0, 5);
        }
        char text[1024];
        std::snprintf(text, sizeof text,
                      "Against the paper's own model (Table 2 alone, no split-bottom factor): level x%.3f (p = %.3g); insertion count p = %.3g "
                      "(best shape %s), measured/simulated by insertion %s; causes: %zu.\n",
                      second->analysis.calibration.factor,
                      second->analysis.calibration.p_value, insertion != d.end() ? insertion->p_value : 1.0,
                      insertion != d.end() ? insertion->best_shape.c_str() : "-", bins.c_str(), second->analysis.causes.size());
        std::printf("%s", text);
        extra += std::string("## Table 2 against the paper's own model\n\n") + text + "\n";
        auto j = nlohmann::ordered_json::parse(json);
        j["papers_own_model"] = nlohmann::ordered_json::parse(validation_json(*second, args.analysis));
        json = assets::json_text(j, 2) + "\n";
    }
    if (!args.json.empty()) {
        if (auto w = outputs.add(args.json, json); !w) {
            std::cerr << "ikebana validate: " << w.error().message << "\n";
            return 1;
        }
    }
    if (!args.report.empty()) {
        for (const auto& [name, text] : validation_report_files(v, args.analysis, extra)) {
            if (auto w = outputs.add(std::filesystem::path(args.report) / name, text); !w) {
                std::cerr << "ikebana validate: --report: " << w.error().message << "\n";
                return 1;
            }
        }
    }
    if (auto done = outputs.commit(); !done) {
        std::cerr << "ikebana validate: " << done.error().message << "\n";
        return 1;
    }
    if (!v.extended_species_json.empty() && !args.write_species.empty()) std::printf("wrote the extended species to %s\n", args.write_species.c_str());
    for (const auto& path : species_written) std::printf("wrote an extended species to %s\n", path.c_str());
    if (!args.json.empty()) std::printf("wrote %s\n", args.json.c_str());
    if (!args.report.empty()) std::printf("wrote %s/report.md\n", args.report.c_str());
    // Asked for a species file that could not be made: the rest is written, and the status says so.
    if (!args.write_species.empty() && v.extended_species_json.empty() && species_written.empty() && !v.analysis.extension.empty()) {
        std::cerr << "ikebana validate: --write-species: not written: " << v.resimulation_note << "\n";
        return 1;
    }
    return 0;
}

} // namespace

void add_validate_command(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("validate", "Compare measured insertions with the simulation: what it gets wrong, why, an extended model and its gain");
    cmd->add_option("measured", args->measured, "Measured trials (CSV, docs/measured-data.md)")->check(CLI::ExistingFile);
    cmd->add_option("--species", args->species, "Species id or file for every row (default: the row's species column, else sunflower)");
    cmd->add_option("--json", args->json, "Write the results as JSON");
    cmd->add_option("--report", args->report, "Write report.md and its figures into this folder");
    cmd->add_option("--write-species", args->write_species, "Write the species with the fitted extension to this file");
    cmd->add_option("--seed", args->analysis.seed, "Seed of the permutations, folds and bootstrap")->capture_default_str();
    cmd->add_option("--permutations", args->analysis.permutations, "Permutations per test")->capture_default_str()->check(CLI::Range(19u, 1000000u));
    auto* alpha = cmd->add_option("--alpha", args->analysis.alpha, "Family-wise significance level")->capture_default_str()->check(finite_in(1e-6, 0.5, ""));
    cmd->add_option("--outliers", args->analysis.outlier_z,
                    "Set aside rows this many robust standard deviations from the others against the model (gross errors; 0: keep every row)")
        ->capture_default_str()
        ->check(CLI::Number & finite_in(0.0, 100.0, ""));
    cmd->add_option("--ignore", args->ignore, "Columns that are not covariates (repeat or comma-separate)")->delimiter(',');
    cmd->add_option("--memory-mb", args->memory_mb,
                    "Working memory the analysis may use (more: the search runs on a sample of flowers; with --search-rows 0 it is refused, naming the widest column)")
        ->capture_default_str()
        ->check(CLI::Range(64u, 1u << 20));
    cmd->add_option("--search-rows", args->analysis.search_rows,
                    "Longer files: the search for causes runs on a random sample of whole flowers of about this many rows, the fit on every row (0: every row)")
        ->capture_default_str()
        ->check(CLI::Range(std::size_t{0}, std::size_t{1} << 40));
    cmd->add_flag("--paper", args->paper, "Run on the paper's Table 2 and report its experiment with the extended species");
    cmd->add_option("--paper-trials", args->paper_trials, "Flowers in the paper's experiment")->capture_default_str()->check(CLI::Range(1u, 1000u));
    cmd->add_option("--paper-hold-trials", args->paper_hold_trials, "Flowers the holding is fitted to the paper's falls over (--paper)")
        ->capture_default_str()
        ->check(CLI::Range(1u, 1000u));
    cmd->callback([args, alpha, &exit_code] {
        args->alpha_given = alpha->count() > 0;
        exit_code = run_validate(*args);
    });
}

} // namespace ikebana::game
