// ikebana: the trainee app (no arguments) and its tools (subcommands).
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include <CLI/CLI.hpp>

#include "game/asset_paths.hpp"
#include "game/cli/assets_command.hpp"
#include "game/cli/devices_command.hpp"
#include "game/cli/experiment_command.hpp"
#include "game/cli/predict_command.hpp"
#include "game/cli/render_command.hpp"
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
    app.add_option("--env", environment, "Environment covariate for extended species in the app, name=value (repeatable)");
    ikebana::game::add_sim_command(app, exit_code);
    ikebana::game::add_species_command(app, exit_code);
    ikebana::game::add_assets_command(app, exit_code);
    ikebana::game::add_experiment_command(app, exit_code);
    ikebana::game::add_force_bench_command(app, exit_code);
    ikebana::game::add_devices_command(app, exit_code);
    ikebana::game::add_predict_command(app, exit_code);
    ikebana::game::add_validate_command(app, exit_code);
    ikebana::game::add_render_command(app, exit_code);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    if (app.get_subcommands().empty()) {
        // The trainee app. The renderer is not built yet, so it runs the default scene headless and
        // says so rather than pretending to open a window.
        const char* display = std::getenv("DISPLAY");
        std::printf("ikebana: %s; the window renderer is not part of this build yet, so the default scene runs "
                    "headless for 10 s on the deterministic clock.\n",
                    display && *display ? "a display is present" : "no display");
        ikebana::game::SimOptions options;
        options.scene = (ikebana::game::asset_dir() / "scenes" / "default.json").string();
        options.seconds = 10.0;
        options.left_device = left_device;
        options.right_device = right_device;
        options.env = environment;
        return ikebana::game::run_sim(options);
    }
    return exit_code;
}
