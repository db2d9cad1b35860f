// ikebana: the trainee app (no arguments) and its tools (subcommands).
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include <CLI/CLI.hpp>

#include "engine/core/utf8.hpp"
#include "game/app/trainee_app.hpp"
#include "game/asset_paths.hpp"
#include "game/progress/progress_db.hpp"
#include "game/cli/assets_command.hpp"
#include "game/cli/devices_command.hpp"
#include "game/cli/experiment_command.hpp"
#include "game/cli/history_command.hpp"
#include "game/cli/report_command.hpp"
#include "game/cli/lesson_command.hpp"
#include "game/cli/predict_command.hpp"
#include "game/cli/render_command.hpp"
#include "game/cli/replay_command.hpp"
#include "game/cli/validate_command.hpp"
#include "game/cli/sim_command.hpp"
#include "game/cli/species_command.hpp"

int main(int argc, char** argv) {
    CLI::App app{"Ikebana: a training simulator for Japanese flower arrangement"};
    app.require_subcommand(0, 1);
    int exit_code = 0;
    // The trainee app picks its hands' devices by itself; these override it.
    std::string left_device = "auto";
    std::string right_device = "auto";
    app.add_option("--left", left_device, "Left hand's device for the app: auto, none, scripted:FILE, replay:FILE, hid:PATH")
        ->capture_default_str();
    app.add_option("--right", right_device, "Right hand's device for the app (as --left)")->capture_default_str();
    std::vector<std::string> environment;
    std::string progress_db;
    bool no_history = false;
    ikebana::game::TraineeAppOptions app_options;
    app.add_option("--stereo", app_options.stereo, "The app's stereo output: sbs, rows, anaglyph or mono (default: as last chosen on the start screen, else mono, a flat screen)");
    app.add_option("--msaa", app_options.msaa, "The app's anti-aliasing, samples a pixel: 1 (none), 2, 4, 8 (0: 4 on a graphics card, none on lavapipe)")
        ->capture_default_str()
        ->check(CLI::IsMember({0u, 1u, 2u, 4u, 8u}));
    app.add_flag("--full-detail", app_options.full_detail,
                 "Draw every mesh as modelled, even a petal a few pixels long (by default those get a coarse copy: on lavapipe a frame's cost is its triangles)");
    app.add_option("--width", app_options.width, "The app's window width")->capture_default_str()->check(CLI::Range(64u, 8192u));
    app.add_option("--height", app_options.height, "The app's window height")->capture_default_str()->check(CLI::Range(64u, 8192u));
    app.add_option("--frames", app_options.frames, "Stop the app after this many frames (0: when the window closes)")->capture_default_str();
    app.add_option("--screenshot", app_options.screenshot, "Write the app's last frame to this PNG");
    app.add_flag("--validation", app_options.validation, "Run the app with the Vulkan validation layer");
    app.add_option("--finish-at-frame", app_options.finish_at_frame, "Finish the training at this frame, as Enter does (demos, tests)");
    app.add_option("--state-out", app_options.state_out, "Write what the window shows as JSON each frame (for scripts that work the window)");
    app.add_option("--env", environment, "Environment covariate for extended species in the app, name=value (repeatable)");
    std::string app_scene = (ikebana::game::asset_dir() / "scenes" / "default.json").string();
    app.add_option("--scene", app_scene, "The scene the app opens")->capture_default_str();
    app.add_option("--lesson", app_options.lesson, "Open a lesson (see `ikebana lesson list`): its container, materials and form; Enter scores against the form");
    app.add_option("--trainee", app_options.trainee, "Who is practising: the name each session is stored under (remembered for next time)");
    app.add_option("--db", progress_db, "Where each scored lesson session is stored (default: $XDG_DATA_HOME/ikebana/progress.sqlite)");
    app.add_flag("--no-history", no_history, "Store no session");
    app.add_flag("--stats", app_options.stats, "Print the session's thread lateness and frame times at the end (else they go to --log)");
    std::string log_path;
    app.add_option("--log", log_path, "Where the session's figures are written (default: $XDG_STATE_HOME/ikebana/last-session.log)");
    app.add_flag("--demonstration", app_options.demonstration, "Store the sessions as a teacher's demonstration (lesson demo --window)");
    app.add_option("--rate", app_options.rates, "Change a rate in the app, e.g. --rate render=60 (haptic, position_estimate, position_check, render)");
    ikebana::game::add_sim_command(app, exit_code);
    ikebana::game::add_species_command(app, exit_code);
    ikebana::game::add_assets_command(app, exit_code);
    ikebana::game::add_experiment_command(app, exit_code);
    ikebana::game::add_force_bench_command(app, exit_code);
    ikebana::game::add_devices_command(app, exit_code);
    ikebana::game::add_predict_command(app, exit_code);
    ikebana::game::add_validate_command(app, exit_code);
    ikebana::game::add_render_command(app, exit_code);
    ikebana::game::add_lesson_command(app, exit_code);
    ikebana::game::add_history_command(app, exit_code);
    ikebana::game::add_report_command(app, exit_code);
    ikebana::game::add_replay_command(app, exit_code);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11 says what was wrong; its own codes (105, 106, 109) are folded into ours: 2, a usage error,
        // as every command's own refusals of its options are. --help is 0.
        return app.exit(e) == 0 ? 0 : 2;
    }
    if (app.get_subcommands().empty()) {
        // The name is stored and written back out as JSON: bytes that are not UTF-8 are refused here,
        // before they reach the trainee's record.
        if (auto words = ikebana::non_utf8_words("--trainee", app_options.trainee)) {
            std::cerr << "ikebana: " << *words << "\n";
            return 2;
        }
        app_options.scene = app_scene;
        app_options.left_device = left_device;
        app_options.right_device = right_device;
        app_options.env = environment;
        // No lesson and no scene asked for: the start screen.
        app_options.start_screen = app_options.lesson.empty() && app.get_option("--scene")->count() == 0;
        app_options.log_path = log_path.empty() ? ikebana::game::default_log_path().string() : log_path;
        if (!no_history) app_options.progress_db = progress_db.empty() ? ikebana::game::default_progress_path().string() : progress_db;
        return ikebana::game::run_trainee_app(app_options);
    }
    return exit_code;
}
