#include "game/cli/experiment_command.hpp"

#include <cstdio>
#include <iostream>

#include <unistd.h>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/option_checks.hpp"
#include "game/experiment/force_scheme_comparison.hpp"
#include "game/experiment/insertion_experiment.hpp"
#include "game/scene/scene.hpp"

namespace ikebana::game {

namespace {
Result<void> write_file(const std::string& path, const std::string& text) { return assets::write_text_file(path, text); }
} // namespace

void add_experiment_command(CLI::App& app, int& exit_code) {
    struct Args {
        ExperimentOptions options;
        std::string json;
        std::string csv;
        std::vector<std::string> env;
    };
    auto args = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("experiment", "Reproduce the paper's repeated-insertion experiment (section 3.1) headless");
    cmd->add_option("--trials", args->options.trials, "Flowers to use")->capture_default_str()->check(CLI::Range(1u, 100000u));
    cmd->add_option("--seed", args->options.seed, "Random seed (breakage, where each insertion lands)")->capture_default_str();
    cmd->add_option("--angle", args->options.angle_deg, "Insertion angle against the horizontal, degrees")->capture_default_str()->check(finite_in(10.0, 90.0, "degrees"));
    cmd->add_option("--species", args->options.species, "Species id or file")->capture_default_str();
    cmd->add_option("--max-insertions", args->options.max_insertions, "Give up on a flower after this many")->capture_default_str()->check(CLI::Range(1u, 1000u));
    cmd->add_option("--env", args->env, "Environment covariate for an extended species, name=value (repeatable)");
    cmd->add_option("--json", args->json, "Write the summary as JSON");
    cmd->add_option("--csv", args->csv, "Write every insertion as CSV");
    cmd->add_option("--threads", args->options.threads, "Run the trials on this many threads (0: one per core); the result is the same")
        ->capture_default_str()->check(CLI::Range(0u, 256u));
    cmd->callback([args, &exit_code] {
        if (auto env = apply_environment_overrides(args->options.environment, args->env); !env) {
            std::cerr << "ikebana experiment: " << env.error().message << "\n";
            exit_code = 2;
            return;
        }
        // Outputs are checked before the work, not refused after it.
        for (const auto& [option, path] : {std::pair{"--json", &args->json}, std::pair{"--csv", &args->csv}}) {
            if (path->empty()) continue;
            if (auto ok = assets::check_output_path(*path); !ok) {
                std::cerr << "ikebana experiment: " << option << ": " << ok.error().message << "\n";
                exit_code = 2;
                return;
            }
        }
        const bool tty = isatty(fileno(stderr)) != 0;
        auto result = run_insertion_experiment(args->options, [tty](std::uint32_t t, std::uint32_t n) {
            if (tty) std::fprintf(stderr, "\rtrials done: %u / %u", t, n);
            if (tty && t == n) std::fprintf(stderr, "\n");
        });
        if (!result) {
            std::cerr << "ikebana experiment: " << result.error().message << "\n";
            exit_code = 2;
            return;
        }
        std::printf("%s", experiment_report(*result, args->options).c_str());
        if (!args->json.empty()) {
            if (auto w = write_file(args->json, experiment_json(*result, args->options)); !w) {
                std::cerr << "ikebana experiment: --json: " << w.error().message << "\n";
                exit_code = 1;
            }
        }
        if (!args->csv.empty()) {
            if (auto w = write_file(args->csv, experiment_csv(*result)); !w) {
                std::cerr << "ikebana experiment: --csv: " << w.error().message << "\n";
                exit_code = 1;
            }
        }
    });
}

void add_force_bench_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string scene;
        double seconds = 8.0;
    };
    auto args = std::make_shared<Args>();
    args->scene = (asset_dir() / "scenes" / "arrangement.json").string();
    auto* bench = app.add_subcommand("bench", "Measurements that print figures");
    bench->require_subcommand(1);
    auto* forces = bench->add_subcommand("forces", "The paper's multi-rate force scheme against full rate, on one scripted session");
    forces->add_option("--scene", args->scene, "Scene with scripted hands")->capture_default_str();
    forces->add_option("--seconds", args->seconds, "Simulated seconds")->capture_default_str()->check(simulated_seconds());
    forces->callback([args, &exit_code] {
        const auto result = compare_force_schemes(args->scene, args->seconds);
        if (!result) {
            std::cerr << "ikebana bench forces: " << result.error().message << "\n";
            exit_code = 2;
            return;
        }
        std::printf("%s", format_force_comparison(*result).c_str());
    });
}

} // namespace ikebana::game
