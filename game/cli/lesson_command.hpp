#pragma once
// `ikebana lesson`: the school forms a trainee practises (assets/lessons/, docs/lesson-format.md).
//   lesson list [--json]                       the shipped lessons
//   lesson check FILE...                       validate lesson files, every problem by its JSON path
//   lesson model LESSON                        the form's model arrangement, as JSON
//   lesson score LESSON --arrangement FILE     score an arrangement given as data [--json OUT]
#include <CLI/CLI.hpp>

namespace ikebana::game {

int list_lessons(bool json);
int check_lesson_files(const std::vector<std::string>& files);
int print_model(const std::string& lesson);
int demo_lesson(const std::string& lesson, const std::string& json_out);
int score_lesson(const std::string& lesson, const std::string& arrangement, const std::string& json_out);
// A recorded session (a window's or `lesson demo --record`'s) played back headless on the
// deterministic clock: 0 when it reaches the recorded score and state hash, 1 when not, 2 on bad input.
int replay_session(const std::string& who, const std::string& folder, const std::string& json_out);
void add_lesson_command(CLI::App& app, int& exit_code);

} // namespace ikebana::game
