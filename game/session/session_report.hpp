#pragma once
// What a teacher hands back after a session (issue 41): the arrangement from the front and from above
// beside the form's model, each criterion's bar and tip, each rule, and the trainee's trend in the
// lesson so far; one page, drawn once with cairo and written as PNG and PDF.
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include "game/lesson/lesson.hpp"
#include "game/progress/progress_db.hpp"
#include "game/training/arrangement.hpp"
#include "game/training/form_score.hpp"

namespace ikebana::game {

struct SessionReport {
    SessionRecord session;             // its result (score, criteria, rules, the arrangement)
    LessonDef lesson;
    Arrangement model;                 // the form's model arrangement
    KenzanFootprint kenzan;
    std::vector<SessionRecord> trend;  // the same trainee's sessions of the lesson up to this one, oldest first
    bool in_database = false;          // false: replayed from its recording, no trend
    // Whether the recording replays to its stored result, checked as `replay --json` does (and against
    // the database's score when it holds the session): said on the page and in `report`'s exit status.
    // `replay_check` says what was found, or why it could not be checked (the folder gone).
    bool checked = false;
    bool replays = false;
    std::string replay_check;
};

// The session recorded in `recording` (a folder with session.json, as `history --json` gives it):
// from the progress database at `db` when it holds it (with the trend), else replayed from the
// recording; either way the recording is replayed and checked against its stored result. A folder
// that is gone is reported from the database alone (not checked). Errors name the folder or the file.
Result<SessionReport> load_session_report(const std::filesystem::path& recording, const std::filesystem::path& db);
// A session in hand (the app's, after Enter), its trend from `db` (none when it is not there) and its
// lesson's model.
Result<SessionReport> session_report_for(SessionRecord session, const ProgressDb* db);

enum class ReportFormat { png, pdf };
// The page's bytes.
Result<std::string> render_session_report(const SessionReport& report, ReportFormat format);
// report.png and report.pdf into `dir` (made when missing), both or neither.
Result<void> write_session_report(const SessionReport& report, const std::filesystem::path& dir);

} // namespace ikebana::game
