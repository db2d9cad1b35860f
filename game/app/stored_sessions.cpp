#include "game/app/stored_sessions.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <limits>
#include <thread>

#include "engine/core/utf8.hpp"
#include "game/world/world.hpp"

namespace ikebana::game {

namespace {
std::string fallback_trainee() {
    const char* user = std::getenv("USER");
    return user && *user && is_utf8(user) ? user : "trainee";
}
} // namespace

StoredSessions::Opened StoredSessions::open(bool lessons_ahead, const LessonDef* lesson) {
    if (o_.progress_db.empty()) return {};
    if (!lessons_ahead && !lesson) return {};
    auto db = ProgressDb::open(o_.progress_db);
    if (!db && db.error().code == ErrorCode::busy) {
        // Another station is writing it: the sessions are stored once it is free (store, finish).
        std::cerr << "ikebana: " << db.error().message << " (sessions are stored when it is free)\n";
        busy_ = true;
        session_.trainee = o_.demonstration ? "teacher" : (!o_.trainee.empty() ? o_.trainee : fallback_trainee());
        session_.kind = o_.demonstration ? "demonstration" : "practice";
        session_.lesson = lesson ? lesson->id : "";
        return {"Results are kept in " + o_.progress_db + " (busy now: stored when it is free)", session_.trainee};
    }
    if (!db) {
        progress_error_ = db.error().message;
        std::cerr << "ikebana: sessions will not be stored: " << progress_error_ << "\n";
        return {"Results are not kept: " + progress_error_, {}};
    }
    progress_.emplace(std::move(db).value());
    std::string trainee = o_.trainee;
    if (trainee.empty()) {
        if (auto remembered = progress_->setting("trainee"); remembered && *remembered) trainee = **remembered;
    } else if (auto kept = progress_->set_setting("trainee", trainee); !kept) {
        std::cerr << "ikebana: the trainee's name is not remembered: " << kept.error().message << "\n";
    }
    if (trainee.empty()) trainee = fallback_trainee();
    session_.trainee = o_.demonstration ? "teacher" : trainee;
    session_.kind = o_.demonstration ? "demonstration" : "practice";
    session_.lesson = lesson ? lesson->id : "";
    return {"Results are kept in " + o_.progress_db, trainee};
}

void StoredSessions::set_trainee(const std::string& name) {
    if (!progress_ || o_.demonstration) return;
    if (!is_utf8(name)) return; // the start screen's field is UTF-8; anything else is not stored
    if (auto kept = progress_->set_setting("trainee", name); !kept) std::cerr << "ikebana: the trainee's name is not remembered: " << kept.error().message << "\n";
    session_.trainee = name;
}

std::optional<std::string> StoredSessions::remembered(const std::string& key) const {
    if (!progress_) return std::nullopt;
    auto value = progress_->setting(key);
    return value && *value ? std::optional<std::string>(**value) : std::nullopt;
}

void StoredSessions::remember(const std::string& key, const std::string& value) {
    if (!progress_) return;
    if (auto kept = progress_->set_setting(key, value); !kept) std::cerr << "ikebana: the " << key << " is not remembered: " << kept.error().message << "\n";
}

std::vector<SessionRecord> StoredSessions::sessions_of(const std::string& trainee) {
    if (!progress_) return {};
    auto mine = progress_->sessions({trainee, ""});
    return mine ? std::move(mine).value() : std::vector<SessionRecord>{};
}

void StoredSessions::begin(World& world, const LessonDef* lesson) {
    if (unsaved_) (void)save_pending(); // the last one still waiting for a busy database: one more try
    recorder_.reset();
    scored_.reset();
    session_.recording.clear();
    session_.lesson = lesson ? lesson->id : "";
    if ((progress_ || busy_) && lesson) start_recording(world, *lesson);
    session_.id = 0;
    session_.started_unix_s = static_cast<std::int64_t>(std::time(nullptr));
    session_start_ = std::chrono::steady_clock::now();
}

// A stored session is recorded: in a folder of its own beside the progress database.
void StoredSessions::start_recording(World& world, const LessonDef& lesson) {
    const auto now = static_cast<std::int64_t>(std::time(nullptr));
    std::string stamp = iso_utc(now);
    std::replace(stamp.begin(), stamp.end(), ':', '-');
    const auto parent = std::filesystem::path(o_.progress_db).parent_path() / "recordings";
    std::error_code ec;
    std::filesystem::create_directories(parent, ec);
    // The folder is this session's only if this process made it: two windows started in one second
    // (two trainees on one database, or CI's two window lessons side by side) once both took
    // "<second>-<lesson>" after both saw it free, and wrote each other's right.csv to pieces. Making a
    // folder is atomic; looking first is not.
    std::filesystem::path folder;
    for (int n = 1; n < 100 && folder.empty(); ++n) {
        const auto candidate = parent / (stamp + "-" + lesson.id + (n > 1 ? "-" + std::to_string(n) : ""));
        if (std::filesystem::create_directory(candidate, ec)) folder = candidate;
    }
    if (folder.empty()) {
        std::cerr << "ikebana: the session is not recorded: no free folder in " << parent.string() << "\n";
        return;
    }
    auto recorder = SessionRecorder::create(folder, /*real_time=*/true);
    if (!recorder) {
        std::cerr << "ikebana: the session is not recorded: " << recorder.error().message << "\n";
        return;
    }
    recorder_ = std::move(recorder).value();
    recorder_->attach(world);
    session_.recording = std::filesystem::absolute(folder).string();
}

bool StoredSessions::finish(World& w, const LessonDef* lesson) {
    if (!recorder_) return true;
    recorder_->detach(w);
    std::int64_t end_us = std::numeric_limits<std::int64_t>::max();
    for (const auto& s : w.schedule.systems()) {
        if (w.schedule.lanes()[s.lane].name == "sim") end_us = std::min(end_us, s.next_due_us);
    }
    const auto folder = recorder_->folder();
    if (lesson && scored_ && scored_->first < end_us) {
        SessionRecorder::WindowRun run;
        run.scored_frame_us = scored_->first;
        run.rates = o_.rates;
        run.env = o_.env;
        for (std::size_t h = 0; h < 2; ++h) run.rate_device[h] = w.hand_devices[h] && !w.hand_devices[h]->capabilities().reports_position;
        if (auto done = recorder_->finish_window(*lesson, session_.kind, run, end_us, scored_->second, w); !done) {
            // The session stays stored, marked as having no recording (it would not replay), and the
            // half-made folder goes.
            recorder_.reset();
            std::error_code ec;
            std::filesystem::remove_all(folder, ec);
            std::cerr << "ikebana: " << done.error().message << "; the session is kept without its recording (it would not replay)\n";
            session_.recording.clear();
            if (!unsaved_ && progress_) {
                if (auto saved = progress_->save(session_); !saved) std::cerr << "ikebana: " << saved.error().message << "\n";
            }
            return false;
        }
        recorder_.reset();
        return true;
    }
    recorder_.reset();
    std::error_code ec;
    std::filesystem::remove_all(folder, ec);
    // Not scored from a frame, so not replayable: a session already stored no longer names the folder.
    if (!session_.recording.empty() && session_.id != 0) {
        session_.recording.clear();
        if (!unsaved_ && progress_) {
            if (auto saved = progress_->save(session_); !saved) std::cerr << "ikebana: " << saved.error().message << "\n";
        }
    }
    return true;
}

// The database, opened now if it was busy at the start.
bool StoredSessions::reopen() {
    if (progress_) return true;
    if (!busy_) return false;
    auto db = ProgressDb::open(o_.progress_db);
    if (!db) {
        if (db.error().code != ErrorCode::busy) {
            busy_ = false;
            progress_error_ = db.error().message;
        }
        return false;
    }
    busy_ = false;
    progress_.emplace(std::move(db).value());
    return true;
}

Result<void> StoredSessions::save_pending() {
    if (!reopen()) return make_error(ErrorCode::busy, o_.progress_db + ": busy (another program, perhaps another Ikebana, is writing it)");
    auto saved = progress_->save(session_);
    if (saved) unsaved_ = false;
    return saved;
}

void StoredSessions::store(const FormScore& result, const components::FrameSnapshot& frame, components::HudInfo& hud) {
    if (!progress_error_.empty()) {
        hud.result.push_back("not stored: " + progress_error_.substr(0, 60));
        return;
    }
    if ((!progress_ && !busy_) || session_.lesson.empty()) return;
    session_.result = result;
    session_.flowers = flower_outcomes(frame);
    session_.duration_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - session_start_).count();
    unsaved_ = true;
    // The recording ends at this score: the frame it was taken from, when one had come (an Enter
    // before the first frame scores nothing the simulation published). Kept whether or not the
    // database took the session now: it is stored later (a busy file) and points at the recording.
    if (recorder_ && !frame.flowers.empty()) scored_ = std::make_pair(frame.sim_time_us, result.score);
    if (auto saved = save_pending(); !saved) {
        if (saved.error().code == ErrorCode::busy) {
            std::cerr << "ikebana: the session is not stored yet: " << saved.error().message << "; it is kept and stored at the next Enter or when the window closes\n";
            hud.result.push_back("not stored yet: the database is busy (kept)");
        } else {
            std::cerr << "ikebana: the session was not stored: " << saved.error().message << "\n";
            hud.result.push_back("not stored (see the terminal)");
        }
        return;
    }
    std::printf("ikebana: stored as session %lld in %s\n", static_cast<long long>(session_.id), progress_->path().c_str());
    std::fflush(stdout);
}

void StoredSessions::store_pending_at_exit() {
    if (!unsaved_ || !progress_error_.empty()) return;
    // The window is closing: a scored session still waiting for a busy database is given time (the
    // other station's writes take milliseconds; a minute means it is stuck).
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    bool said = false;
    for (;;) {
        if (progress_) progress_->set_busy_wait_ms(1000);
        auto saved = save_pending();
        if (saved) {
            std::printf("ikebana: stored as session %lld in %s\n", static_cast<long long>(session_.id), progress_->path().c_str());
            std::fflush(stdout);
            return;
        }
        if (saved.error().code != ErrorCode::busy || std::chrono::steady_clock::now() > until) {
            std::cerr << "ikebana: the session was not stored: " << saved.error().message << "\n";
            if (!session_.recording.empty()) std::cerr << "ikebana: its recording is kept in " << session_.recording << "\n";
            return;
        }
        if (!said) std::cerr << "ikebana: waiting for " << o_.progress_db << " to store the session (another program is writing it)\n";
        said = true;
        if (!progress_) std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
}

} // namespace ikebana::game
