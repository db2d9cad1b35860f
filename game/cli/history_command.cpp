#include "game/cli/history_command.hpp"

#include "engine/core/utf8.hpp"

#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "engine/assets/json_checker.hpp"
#include "engine/assets/files.hpp"
#include "game/progress/progress_db.hpp"
#include "game/progress/progress_plot.hpp"

namespace ikebana::game {
namespace {

using OJson = nlohmann::ordered_json;

OJson session_json(const SessionRecord& s) {
    // The result as `lesson score --json` gives it, under the session's own fields.
    const OJson result = OJson::parse(s.result.json(-1));
    OJson flowers = OJson::array();
    for (const auto& f : s.flowers) flowers.push_back({{"species", f.species}, {"insertions", f.insertions}, {"broken", f.broken}, {"fallen", f.fallen}});
    return {{"id", s.id},
            {"lesson", s.lesson},
            {"trainee", s.trainee},
            {"kind", s.kind},
            {"started", iso_utc(s.started_unix_s)},
            {"duration_s", std::round(s.duration_s * 10.0) / 10.0},
            {"score", result["score"]},
            {"recording", s.recording.empty() ? OJson(nullptr) : OJson(utf8_or_replacement(s.recording))},
            // JSON text is UTF-8: a folder whose name is not (a Latin-1 path) is shown with U+FFFD above and
            // cannot be passed back; `report --id` takes the session by its id instead.
            {"recording_is_utf8", s.recording.empty() || is_utf8(s.recording)},
            {"flowers", flowers},
            {"how", result["how"]},
            {"criteria", result["criteria"]},
            {"rules", result["rules"]},
            {"arrangement", result["arrangement"]}};
}

std::string whose(const HistoryArgs& a) {
    std::string who = a.trainee.empty() ? "everyone" : a.trainee;
    if (!a.lesson.empty()) who += ", " + a.lesson;
    return who;
}

} // namespace

int show_history(const HistoryArgs& args) {
    const std::string who = "ikebana history: ";
    if (!args.plot.empty()) {
        if (auto format = plot_format_of(args.plot); !format) {
            std::cerr << who << "--plot: " << format.error().message << "\n";
            return 2;
        }
        if (auto ok = assets::check_output_path(args.plot); !ok) {
            std::cerr << who << "--plot: " << ok.error().message << "\n";
            return 2;
        }
    }
    const std::filesystem::path path = args.db.empty() ? default_progress_path() : std::filesystem::path(args.db);
    std::vector<SessionRecord> sessions;
    auto db = ProgressDb::open_read_only(path);
    if (!db && db.error().code != ErrorCode::not_found) {
        std::cerr << who << db.error().message << "\n";
        return 1;
    }
    if (db) {
        auto read = db->sessions({args.trainee, args.lesson});
        if (!read) {
            std::cerr << who << read.error().message << "\n";
            return 1;
        }
        sessions = std::move(*read);
    }
    if (!args.plot.empty()) {
        if (auto w = write_progress_plot(sessions, "Ikebana progress: " + whose(args), args.plot); !w) {
            std::cerr << who << "--plot: " << w.error().message << "\n";
            return 1;
        }
    }
    if (args.json) {
        OJson list = OJson::array();
        for (const auto& s : sessions) list.push_back(session_json(s));
        std::printf("%s\n", assets::json_text(OJson{{"database", path.string()}, {"sessions", list}}, 1).c_str());
        return 0;
    }
    if (sessions.empty()) {
        std::printf("no sessions of %s yet in %s (a lesson's Enter, or `ikebana lesson demo`, stores one)\n", whose(args).c_str(), path.string().c_str());
    } else {
        std::printf("%zu session(s) of %s in %s, oldest first\n", sessions.size(), terminal_text(whose(args)).c_str(), terminal_text(path.string()).c_str());
        std::printf("  %4s  %-17s  %-24s  %-12s  %-13s  %5s  %7s\n", "id", "started (UTC)", "lesson", "trainee", "kind", "score", "minutes");
        for (const auto& s : sessions) {
            std::string started = iso_utc(s.started_unix_s).substr(0, 16);
            started[10] = ' ';
            // Names from the database (another program may have written them): shown, never sent as controls.
            std::printf("  %4lld  %-17s  %-24s  %-12s  %-13s  %5.1f  %7.1f\n", static_cast<long long>(s.id), started.c_str(), terminal_text(s.lesson).c_str(),
                        terminal_text(s.trainee).c_str(), terminal_text(s.kind).c_str(), s.result.score, s.duration_s / 60.0);
        }
    }
    if (!args.plot.empty()) std::printf("plot of the scores and each criterion's trend in %s\n", args.plot.c_str());
    return 0;
}

void add_history_command(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<HistoryArgs>();
    auto* cmd = app.add_subcommand("history", "The sessions practised and demonstrated, oldest first, from the progress database; --plot draws the scores over time");
    cmd->add_option("--trainee", args->trainee, "Only this trainee's sessions");
    cmd->add_option("--lesson", args->lesson, "Only this lesson's sessions (its id)");
    cmd->add_flag("--json", args->json, "Print the sessions as JSON (each with its criteria, rules, flowers and arrangement)");
    cmd->add_option("--plot", args->plot, "Also draw the score over time per lesson, with each criterion's trend (.png or .svg)");
    cmd->add_option("--db", args->db, "The progress database (default: $XDG_DATA_HOME/ikebana/progress.sqlite)");
    cmd->callback([args, &exit_code] { exit_code = show_history(*args); });
}

} // namespace ikebana::game
