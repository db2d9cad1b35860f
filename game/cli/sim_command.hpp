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
};

// `ikebana sim`: runs a scene headless on the deterministic (or real-time) clock.
void add_sim_command(CLI::App& app, int& exit_code);
int run_sim(const SimOptions& options);

} // namespace ikebana::game
