#include "game/cli/report_command.hpp"

#include <cstdio>
#include <iostream>
#include <memory>

#include "game/progress/progress_db.hpp"
#include "game/session/session_report.hpp"

namespace ikebana::game {

namespace {

struct ReportArgs {
    std::string session, out, db;
};

int make_report(const ReportArgs& args) {
    const std::filesystem::path db = args.db.empty() ? default_progress_path() : std::filesystem::path(args.db);
    auto report = load_session_report(args.session, db);
    if (!report) {
        std::cerr << "ikebana report: " << report.error().message << "\n";
        return 2;
    }
    if (auto written = write_session_report(*report, args.out); !written) {
        std::cerr << "ikebana report: " << written.error().message << "\n";
        return 1;
    }
    std::printf("%s, %s: %.0f / 100%s\n", report->lesson.title.c_str(), report->session.trainee.empty() ? "a trainee" : report->session.trainee.c_str(),
                report->session.result.score, report->in_database ? "" : " (not in the progress database: replayed from its recording, no trend)");
    std::printf("wrote %s and %s\n", (std::filesystem::path(args.out) / "report.png").string().c_str(), (std::filesystem::path(args.out) / "report.pdf").string().c_str());
    // Whether the page shows what the recording replays to; the status says it too (0 only when it does).
    if (report->checked && report->replays) {
        std::printf("%s\n", report->replay_check.c_str());
        return 0;
    }
    std::cerr << "ikebana report: " << report->replay_check << "\n";
    return 1;
}

} // namespace

void add_report_command(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<ReportArgs>();
    auto* cmd = app.add_subcommand("report", "A session's report for the trainee: the arrangement from the front and above beside the form's model, each "
                                             "criterion's bar and tip, the rules, the trend; as PNG and PDF");
    cmd->add_option("session", args->session, "The session's recording folder (`history --json` gives it as \"recording\")")->required();
    cmd->add_option("--out", args->out, "The folder for report.png and report.pdf")->required();
    cmd->add_option("--db", args->db, "The progress database (default: $XDG_DATA_HOME/ikebana/progress.sqlite)");
    cmd->callback([args, &exit_code] { exit_code = make_report(*args); });
}

} // namespace ikebana::game
