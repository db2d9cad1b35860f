#include "game/cli/report_command.hpp"

#include <cstdio>
#include <iostream>
#include <memory>

#include "engine/core/utf8.hpp"
#include "game/progress/progress_db.hpp"
#include "game/session/session_report.hpp"

namespace ikebana::game {

namespace {

struct ReportArgs {
    std::string session, out, db;
    std::int64_t id = -1;
};

// The recording folder of the session with id `id` in the progress database (`history` gives ids): its
// bytes as stored, whatever they are (a folder whose name is not UTF-8 cannot pass through JSON).
Result<std::filesystem::path> recording_of(std::int64_t id, const std::filesystem::path& db) {
    auto progress = ProgressDb::open_read_only(db);
    if (!progress) return std::move(progress).error();
    auto sessions = progress->sessions();
    if (!sessions) return std::move(sessions).error();
    for (const auto& s : *sessions) {
        if (s.id != id) continue;
        if (s.recording.empty()) return make_error(ErrorCode::not_found, "session " + std::to_string(id) + " was not recorded: there is nothing to report from");
        return std::filesystem::path(s.recording);
    }
    return make_error(ErrorCode::not_found, "no session " + std::to_string(id) + " in " + db.string() + " (`ikebana history` lists them)");
}

int make_report(const ReportArgs& args) {
    const std::filesystem::path db = args.db.empty() ? default_progress_path() : std::filesystem::path(args.db);
    if (args.session.empty() == (args.id < 0)) {
        std::cerr << "ikebana report: give the session's recording folder or --id N, one of them\n";
        return 2;
    }
    std::filesystem::path recording = args.session;
    if (args.id >= 0) {
        auto found = recording_of(args.id, db);
        if (!found) {
            std::cerr << "ikebana report: --id " << args.id << ": " << found.error().message << "\n";
            return 2;
        }
        recording = std::move(found).value();
    }
    auto report = load_session_report(recording, db);
    if (!report) {
        std::cerr << "ikebana report: " << terminal_text(report.error().message) << "\n";
        return 2;
    }
    if (auto written = write_session_report(*report, args.out); !written) {
        std::cerr << "ikebana report: " << written.error().message << "\n";
        return 1;
    }
    std::printf("%s, %s: %.1f / 100%s\n", terminal_text(report->lesson.title).c_str(),
                report->session.trainee.empty() ? "a trainee" : terminal_text(report->session.trainee).c_str(),
                report->session.result.score, report->in_database ? "" : " (not in the progress database: replayed from its recording, no trend)");
    std::printf("wrote %s and %s\n", terminal_text((std::filesystem::path(args.out) / "report.png").string()).c_str(),
                terminal_text((std::filesystem::path(args.out) / "report.pdf").string()).c_str());
    // Whether the page shows what the recording replays to; the status says it too (0 only when it does).
    if (report->checked && report->replays) {
        std::printf("%s\n", report->replay_check.c_str());
        return 0;
    }
    std::cerr << "ikebana report: " << terminal_text(report->replay_check) << "\n";
    return 1;
}

} // namespace

void add_report_command(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<ReportArgs>();
    auto* cmd = app.add_subcommand("report", "A session's report for the trainee: the arrangement from the front and above beside the form's model, each "
                                             "criterion's bar and tip, the rules, the trend; as PNG and PDF");
    cmd->add_option("session", args->session, "The session's recording folder (`history --json` gives it as \"recording\")");
    cmd->add_option("--id", args->id, "Or the session's id in the progress database (`history` shows it)")->check(CLI::NonNegativeNumber);
    cmd->add_option("--out", args->out, "The folder for report.png and report.pdf")->required();
    cmd->add_option("--db", args->db, "The progress database (default: $XDG_DATA_HOME/ikebana/progress.sqlite)");
    cmd->callback([args, &exit_code] { exit_code = make_report(*args); });
}

} // namespace ikebana::game
