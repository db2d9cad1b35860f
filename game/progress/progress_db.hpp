#pragma once
// The trainee's progress: every finished session (a lesson scored at Enter, or a teacher's
// demonstration) kept in a SQLite database, by default $XDG_DATA_HOME/ikebana/progress.sqlite
// (~/.local/share/ikebana/ without XDG_DATA_HOME).
//
// A session is written in one transaction, so a killed app leaves every earlier session whole (and
// the one being written either whole or absent); the journal is a write-ahead log. The file is the
// trainee's record of months of practice: a file that is not ours (another program's database,
// damaged bytes, a newer schema) is reported and never written to, not even by opening it - it is
// checked through a read-only connection before a writing one is opened. Two stations may share one
// file: each waits for the other's write, and a file that stays busy is said to be busy
// (ErrorCode::busy), never damaged.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "components/snapshot.hpp"
#include "engine/core/result.hpp"
#include "game/training/form_score.hpp"

struct sqlite3;

namespace ikebana::game {

// How a flower ended the session.
struct FlowerOutcome {
    std::string species;
    std::uint32_t insertions = 0; // over its life, across cuts
    bool broken = false;          // its bottom broke
    bool fallen = false;
};

// Each flower of a frame as it ends a session.
[[nodiscard]] std::vector<FlowerOutcome> flower_outcomes(const components::FrameSnapshot& frame);

struct SessionRecord {
    std::int64_t id = 0;            // the database's (0: not stored yet)
    std::string lesson;             // the lesson's id
    std::string trainee;
    std::string kind = "practice";  // "practice" or "demonstration"
    std::int64_t started_unix_s = 0;
    double duration_s = 0.0;        // from the start to the (last) score
    FormScore result;               // score, each criterion and rule, the arrangement
    std::vector<FlowerOutcome> flowers;
    std::string recording;          // the folder its recording is in (empty: none)
};

struct SessionFilter {
    std::string trainee; // empty: everyone
    std::string lesson;  // empty: every lesson
};

// Whether a database may be at `path`: missing, or a regular file (not a FIFO, a device, a folder or
// a link); what open() checks first, for a command to ask before it starts a long run.
Result<void> check_progress_path(const std::filesystem::path& path);
// $XDG_DATA_HOME/ikebana/progress.sqlite, or ~/.local/share/ikebana/progress.sqlite.
[[nodiscard]] std::filesystem::path default_progress_path();
// $XDG_STATE_HOME/ikebana/last-session.log, or ~/.local/state/ikebana/last-session.log: the app's
// figures of its last session (threads' lateness, frame times).
[[nodiscard]] std::filesystem::path default_log_path();
// "2026-11-25T07:12:03Z"
[[nodiscard]] std::string iso_utc(std::int64_t unix_s);

class ProgressDb {
public:
    // For writing: creates the file (and its folder) when it does not exist. Errors name the file.
    static Result<ProgressDb> open(const std::filesystem::path& path);
    // For reading: a file that does not exist is not_found; nothing is created or written.
    static Result<ProgressDb> open_read_only(const std::filesystem::path& path);

    ProgressDb(ProgressDb&& other) noexcept;
    ProgressDb& operator=(ProgressDb&& other) noexcept;
    ProgressDb(const ProgressDb&) = delete;
    ProgressDb& operator=(const ProgressDb&) = delete;
    ~ProgressDb();

    // A new session (id 0) is added and given its id; a stored one (a lesson scored again at a later
    // Enter) is replaced whole. One transaction either way.
    Result<void> save(SessionRecord& session);
    // Oldest first.
    Result<std::vector<SessionRecord>> sessions(const SessionFilter& filter = {}) const;
    // Small remembered things: the trainee's name.
    Result<std::optional<std::string>> setting(const std::string& key) const;
    Result<void> set_setting(const std::string& key, const std::string& value);

    // How long a save waits for another station's write before it fails with ErrorCode::busy (250 ms
    // after open: an Enter's frame waits for it).
    void set_busy_wait_ms(int ms);

    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

private:
    ProgressDb(sqlite3* db, std::filesystem::path path) : db_(db), path_(std::move(path)) {}
    sqlite3* db_ = nullptr;
    std::filesystem::path path_;
};

} // namespace ikebana::game
