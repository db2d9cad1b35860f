#pragma once
// The trainee window's record of its sessions: the progress database (each scored session stored at
// its first Enter and again at each later one) and each stored session's recording (the hands'
// samples, cuts, the camera's turns, the clock's skips) for `ikebana replay`, made with the world and
// finished when it stops, at the last Enter's score. A database that cannot be used is said once, and
// the lesson goes on without storing: a damaged file is never written to. A database another station
// is writing is busy, not damaged: a session it could not take is kept and stored at the next Enter,
// the next session's start, or when the window closes.
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "components/presentation.hpp"
#include "components/snapshot.hpp"
#include "game/app/trainee_app.hpp"
#include "game/lesson/lesson.hpp"
#include "game/progress/progress_db.hpp"
#include "game/session/lesson_session.hpp"
#include "game/training/form_score.hpp"

namespace ikebana::game {

class World;

class StoredSessions {
public:
    explicit StoredSessions(const TraineeAppOptions& options) : o_(options) {}

    // Opens the database when sessions are stored (--db) and there is something to score (a lesson,
    // or the start screen that leads to one). Says where results are kept, or why they are not (for
    // the start screen), and whose they are: --trainee (remembered), the remembered name, or $USER.
    struct Opened {
        std::string note;
        std::string trainee;
    };
    Opened open(bool lessons_ahead, const LessonDef* lesson);
    [[nodiscard]] ProgressDb* db() noexcept { return progress_ ? &*progress_ : nullptr; }
    [[nodiscard]] const std::string& trainee() const noexcept { return session_.trainee; }
    // The session as its last Enter stored it (its result empty before the first).
    [[nodiscard]] const SessionRecord& session() const noexcept { return session_; }
    // The name chosen on the start screen, remembered for the next time (not for a demonstration).
    void set_trainee(const std::string& name);
    // A setting kept in the database from one run to the next (the display chosen), and keeping one;
    // nothing without a database, and a setting that cannot be kept is said, not fatal.
    [[nodiscard]] std::optional<std::string> remembered(const std::string& key) const;
    void remember(const std::string& key, const std::string& value);
    // This trainee's sessions, oldest first (none without a database).
    [[nodiscard]] std::vector<SessionRecord> sessions_of(const std::string& trainee);

    // A new session (at the start, and after R): stored as a new one at its first Enter, recorded from
    // now on when it will be stored.
    void begin(World& world, const LessonDef* lesson);
    // Each Enter stores the session as it now stands (the first adds it, later ones replace it); what
    // went wrong is added to the HUD's result.
    void store(const FormScore& result, const components::FrameSnapshot& frame, components::HudInfo& hud);
    // The recording's command log, while there is one (the clock's skips go there).
    [[nodiscard]] SessionRecorder* recorder() noexcept { return recorder_.get(); }
    // When the world has stopped: session.json with the last Enter's score, or no recording at all when
    // nothing was scored (no stored session points at it).
    // False when the session's recording could not be written whole (a full disk): it was said, the
    // session is kept without it, and the app ends with status 1 as `sim --record` does.
    [[nodiscard]] bool finish(World& world, const LessonDef* lesson);
    // When the window closes: a scored session the database was too busy to take is stored now,
    // waiting up to a minute for the other station.
    void store_pending_at_exit();

private:
    bool reopen();
    Result<void> save_pending();
    void start_recording(World& world, const LessonDef& lesson);

    const TraineeAppOptions& o_;
    std::optional<ProgressDb> progress_;
    std::string progress_error_; // why sessions are not stored (said once, and under each result)
    bool busy_ = false;          // the database was busy at the start: opened at the next store
    bool unsaved_ = false;       // the last scored session is not in the database yet (it was busy)
    SessionRecord session_;
    std::chrono::steady_clock::time_point session_start_ = std::chrono::steady_clock::now();
    std::unique_ptr<SessionRecorder> recorder_;
    std::optional<std::pair<std::int64_t, double>> scored_; // the scored frame's time (us) and the score
};

} // namespace ikebana::game
