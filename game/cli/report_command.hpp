#pragma once
// `ikebana report SESSION --out DIR [--db FILE]`: what a teacher hands back after a session
// (game/session/session_report.hpp), as DIR/report.png and DIR/report.pdf.
#include <CLI/CLI.hpp>

namespace ikebana::game {

void add_report_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
