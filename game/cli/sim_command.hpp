#pragma once
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ikebana::game {

struct SimOptions {
    std::string scene;
    double seconds = 10.0;
    bool stats = false;
    bool hash = false;
    bool realtime = false;
    std::vector<std::string> rates;
    std::string count_lane; // --count-lane: the lane whose systems callgrind counts (empty: everything)
    std::string left_device;  // empty: what the scene says (see game/devices/hand_device_selection.hpp)
    std::string right_device;
    std::string record_dir;   // when set: every device sample of each hand, to replay later
    std::string force_scheme; // empty: the scene's
    std::vector<std::string> env; // name=value over the scene's "environment" (an extended species' covariates)
};

// `ikebana sim`: runs a scene headless on the deterministic (or real-time) clock.
void add_sim_command(CLI::App& app, int& exit_code);
int run_sim(const SimOptions& options);

} // namespace ikebana::game
