#pragma once
// `ikebana history [--trainee NAME] [--lesson ID] [--json] [--plot OUT.svg|OUT.png] [--db FILE]`: the
// sessions in the progress database (game/progress/progress_db.hpp), oldest first, and a plot of the
// score over time per lesson with each criterion's trend.
#include <CLI/CLI.hpp>

namespace ikebana::game {

struct HistoryArgs {
    std::string trainee, lesson, plot, db;
    bool json = false;
};
int show_history(const HistoryArgs& args);
void add_history_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
