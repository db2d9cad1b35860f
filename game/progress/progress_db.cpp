#include "game/progress/progress_db.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include <unistd.h>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <system_error>
#include <utility>

#include <sqlite3.h>

#include "engine/core/utf8.hpp"

namespace ikebana::game {
namespace {

// "IKEB": written into the file's header, so a database of another program is told apart from ours.
constexpr std::int32_t application_id = 0x494B4542;
constexpr int schema_version = 1;

constexpr const char* schema_sql = R"sql(
CREATE TABLE sessions(
  id INTEGER PRIMARY KEY,
  lesson TEXT NOT NULL,
  trainee TEXT NOT NULL,
  kind TEXT NOT NULL CHECK (kind IN ('practice', 'demonstration')),
  started_unix_s INTEGER NOT NULL,
  duration_s REAL NOT NULL,
  score REAL NOT NULL,
  how TEXT NOT NULL,
  arrangement TEXT NOT NULL,
  recording TEXT NOT NULL);
CREATE TABLE criteria(
  session_id INTEGER NOT NULL REFERENCES sessions(id) ON DELETE CASCADE,
  position INTEGER NOT NULL,
  stem TEXT NOT NULL, name TEXT NOT NULL, target REAL NOT NULL, tolerance REAL NOT NULL, measured REAL,
  points REAL NOT NULL, max_points REAL NOT NULL, tip TEXT NOT NULL);
CREATE TABLE rules(
  session_id INTEGER NOT NULL REFERENCES sessions(id) ON DELETE CASCADE,
  position INTEGER NOT NULL,
  name TEXT NOT NULL, ok INTEGER NOT NULL, points REAL NOT NULL, max_points REAL NOT NULL, tip TEXT NOT NULL);
CREATE TABLE flowers(
  session_id INTEGER NOT NULL REFERENCES sessions(id) ON DELETE CASCADE,
  position INTEGER NOT NULL,
  species TEXT NOT NULL, insertions INTEGER NOT NULL, broken INTEGER NOT NULL, fallen INTEGER NOT NULL);
CREATE INDEX criteria_of_session ON criteria(session_id, position);
CREATE INDEX rules_of_session ON rules(session_id, position);
CREATE INDEX flowers_of_session ON flowers(session_id, position);
CREATE TABLE settings(key TEXT PRIMARY KEY, value TEXT NOT NULL);
)sql";

const char* left_alone = "; it is left as it is (move it aside to start a new record)";

// Two stations on one database: while one writes (a session, or the tables of a new file), the
// other waits this long, then is told the file is busy, never that it is damaged.
constexpr int open_wait_ms = 5000;  // at start-up and for a command
constexpr int save_wait_ms = 250;   // an Enter in the window: its frame waits (StoredSessions tries again later)

bool is_busy(int code) { return (code & 0xFF) == SQLITE_BUSY || (code & 0xFF) == SQLITE_LOCKED; } // and their extended codes

Error busy_error(const std::filesystem::path& path, const std::string& doing) {
    return make_error(ErrorCode::busy, path.string() + ": " + doing + ": busy (another program, perhaps another Ikebana, is writing it); try again");
}

Error db_error(const std::filesystem::path& path, sqlite3* db, const std::string& doing) {
    if (db && is_busy(sqlite3_errcode(db))) return busy_error(path, doing);
    return make_error(ErrorCode::io_error, path.string() + ": " + doing + ": " + (db ? sqlite3_errmsg(db) : "out of memory"));
}

// One prepared statement, finalized on every path out.
class Statement {
public:
    Statement(sqlite3* db, const char* sql) { rc_ = sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;
    ~Statement() { sqlite3_finalize(stmt_); }
    [[nodiscard]] bool prepared() const { return rc_ == SQLITE_OK && stmt_; }
    sqlite3_stmt* get() const { return stmt_; }
    void bind(int i, const std::string& s) { sqlite3_bind_text(stmt_, i, s.data(), static_cast<int>(s.size()), SQLITE_TRANSIENT); }
    void bind(int i, double v) { sqlite3_bind_double(stmt_, i, v); }
    void bind(int i, std::int64_t v) { sqlite3_bind_int64(stmt_, i, v); }
    void bind_null(int i) { sqlite3_bind_null(stmt_, i); }
    void bind(int i, const std::optional<double>& v) {
        if (v) bind(i, *v);
        else bind_null(i);
    }
    // One row: the values bound to ?1, ?2, ... in order, run, and the statement made ready for the next.
    template <typename... Values>
    bool row(const Values&... values) {
        int i = 0;
        (bind(++i, values), ...);
        const bool done = step() == SQLITE_DONE;
        reset();
        return done;
    }
    int step() { return sqlite3_step(stmt_); }
    void reset() {
        sqlite3_reset(stmt_);
        sqlite3_clear_bindings(stmt_);
    }
    [[nodiscard]] std::string text(int i) const {
        const auto* t = sqlite3_column_text(stmt_, i);
        // A cell another program wrote may hold bytes that are not UTF-8 (SQLite does not check, and
        // integrity_check passes): read as U+FFFD, so the history still reads and prints.
        return t ? utf8_or_replacement({reinterpret_cast<const char*>(t), static_cast<std::size_t>(sqlite3_column_bytes(stmt_, i))}) : std::string{};
    }
    // The bytes as stored: a path names a folder whatever its bytes (a Latin-1 folder name), and a path
    // made readable would name another folder.
    [[nodiscard]] std::string bytes(int i) const {
        const auto* t = sqlite3_column_text(stmt_, i);
        return t ? std::string(reinterpret_cast<const char*>(t), static_cast<std::size_t>(sqlite3_column_bytes(stmt_, i))) : std::string{};
    }
    [[nodiscard]] double real(int i) const { return sqlite3_column_double(stmt_, i); }
    [[nodiscard]] std::int64_t integer(int i) const { return sqlite3_column_int64(stmt_, i); }
    [[nodiscard]] bool null(int i) const { return sqlite3_column_type(stmt_, i) == SQLITE_NULL; }

private:
    sqlite3_stmt* stmt_ = nullptr;
    int rc_ = SQLITE_ERROR;
};

// A single integer from a pragma or a count; errors keep SQLite's code (SQLITE_NOTADB: not a database).
Result<std::int64_t> single_integer(sqlite3* db, const char* sql, int& code) {
    Statement s(db, sql);
    if (!s.prepared()) {
        code = sqlite3_errcode(db);
        return make_error(ErrorCode::parse_error, sqlite3_errmsg(db));
    }
    const int rc = s.step();
    if (rc != SQLITE_ROW) {
        code = sqlite3_errcode(db);
        return make_error(ErrorCode::parse_error, sqlite3_errmsg(db));
    }
    return s.integer(0);
}

struct Closer {
    sqlite3* db;
    ~Closer() {
        if (db) sqlite3_close_v2(db);
    }
};

// The database's path gets the checks every input path gets (assets/files.hpp): a FIFO would block
// the open for ever, and a device (`/dev/zero`) read as an empty database had a journal created beside
// it. Anything but a regular file (or a missing one) is refused before SQLite sees it.
Result<void> check_regular_path(const std::filesystem::path& path) {
    std::error_code ec;
    const auto status = std::filesystem::symlink_status(path, ec);
    if (ec || status.type() == std::filesystem::file_type::not_found || status.type() == std::filesystem::file_type::regular) return {};
    switch (status.type()) {
    case std::filesystem::file_type::directory: return make_error(ErrorCode::io_error, path.string() + ": a folder, not a progress database");
    case std::filesystem::file_type::symlink: return make_error(ErrorCode::io_error, path.string() + ": a symbolic link, not a progress database (name the file itself)");
    case std::filesystem::file_type::fifo: return make_error(ErrorCode::io_error, path.string() + ": a FIFO, not a progress database");
    default: return make_error(ErrorCode::io_error, path.string() + ": a device or socket, not a progress database");
    }
}

// Looks at an existing file through a read-only connection. Returns whether it still needs our
// tables (an empty file, or a database with nothing in it).
Result<bool> check_existing(const std::filesystem::path& path) {
    // A writer killed inside a transaction leaves a hot journal, which only a connection that may write
    // can roll back: read-only, the file read as "damaged (attempt to write a readonly database)" (the
    // kill test, once, with the app killed 30 ms in, while it made its tables). Opened for writing and
    // read once, SQLite puts the file back as it was before that transaction, as any open would.
    if (std::error_code ec; std::filesystem::exists(path.string() + "-journal", ec)) {
        sqlite3* rw = nullptr;
        if (sqlite3_open_v2(path.c_str(), &rw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOFOLLOW, nullptr) == SQLITE_OK) {
            sqlite3_busy_timeout(rw, open_wait_ms);
            sqlite3_exec(rw, "SELECT count(*) FROM sqlite_schema", nullptr, nullptr, nullptr);
        }
        sqlite3_close_v2(rw);
    }
    sqlite3* db = nullptr;
    const int rc = sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOFOLLOW, nullptr);
    Closer closer{db};
    if (rc != SQLITE_OK) return make_error(ErrorCode::io_error, path.string() + ": cannot be opened: " + (db ? sqlite3_errmsg(db) : "out of memory"));
    sqlite3_busy_timeout(db, open_wait_ms);
    // One snapshot for every look below: read apart, a station making the tables of a new file at the
    // same moment was seen with no application id yet and its tables already there ("another
    // program's database", 1 run in 60 of the two-stations test). The transaction ends when the
    // connection closes.
    sqlite3_exec(db, "BEGIN", nullptr, nullptr, nullptr);
    int code = SQLITE_OK;
    const auto app = single_integer(db, "PRAGMA application_id", code);
    if (!app) {
        if (is_busy(code)) return busy_error(path, "cannot be read now");
        if (code == SQLITE_NOTADB) return make_error(ErrorCode::parse_error, path.string() + ": not an Ikebana progress database (not an SQLite file)" + left_alone);
        return make_error(ErrorCode::parse_error, path.string() + ": damaged (" + app.error().message + ")" + left_alone);
    }
    const auto tables = single_integer(db, "SELECT count(*) FROM sqlite_schema", code);
    if (!tables && is_busy(code)) return busy_error(path, "cannot be read now");
    if (!tables) return make_error(ErrorCode::parse_error, path.string() + ": damaged (" + tables.error().message + ")" + left_alone);
    if (*app != application_id) {
        if (*app == 0 && *tables == 0) return true; // an empty file: ours to fill
        char id[16];
        std::snprintf(id, sizeof id, "0x%08llx", static_cast<unsigned long long>(static_cast<std::uint32_t>(*app)));
        return make_error(ErrorCode::parse_error, path.string() + ": an SQLite database of another program (application id " + id +
                                                      ", not Ikebana's)" + left_alone);
    }
    const auto version = single_integer(db, "PRAGMA user_version", code);
    if (!version) return make_error(ErrorCode::parse_error, path.string() + ": damaged (" + version.error().message + ")" + left_alone);
    if (*version > schema_version)
        return make_error(ErrorCode::parse_error, path.string() + ": written by a newer Ikebana (its schema is version " + std::to_string(*version) +
                                                      ", this one reads " + std::to_string(schema_version) + ")" + left_alone);
    // Damage inside the file (a torn page, bytes overwritten) shows here rather than halfway through
    // writing a session. The full check, not quick_check: an index that misses rows of its table
    // passes quick_check, and a session saved into such a file was read back without its criteria (a
    // fuzzer's file); a progress record is small enough to check whole at every open.
    Statement check(db, "PRAGMA integrity_check(1)");
    const int checked = check.prepared() ? check.step() : sqlite3_errcode(db);
    if (checked != SQLITE_ROW && is_busy(sqlite3_errcode(db))) return busy_error(path, "cannot be read now");
    if (checked != SQLITE_ROW)
        return make_error(ErrorCode::parse_error, path.string() + ": damaged (" + sqlite3_errmsg(db) + ")" + left_alone);
    if (const auto verdict = check.text(0); verdict != "ok") return make_error(ErrorCode::parse_error, path.string() + ": damaged (" + verdict + ")" + left_alone);
    if (*version < schema_version) return make_error(ErrorCode::parse_error, path.string() + ": damaged (no schema version)" + left_alone);
    // Our header on someone else's tables (or ours with one dropped) would fail at the first save.
    const auto ours = single_integer(db, "SELECT count(*) FROM sqlite_schema WHERE type = 'table' AND name IN ('sessions', 'criteria', 'rules', 'flowers', 'settings')", code);
    if (!ours) return make_error(ErrorCode::parse_error, path.string() + ": damaged (" + ours.error().message + ")" + left_alone);
    if (*ours != 5) return make_error(ErrorCode::parse_error, path.string() + ": damaged (Ikebana's header, but not its tables)" + left_alone);
    return false;
}

Result<void> exec(sqlite3* db, const std::filesystem::path& path, const char* sql, const std::string& doing) {
    char* message = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &message) != SQLITE_OK) {
        std::string why = message ? message : sqlite3_errmsg(db);
        sqlite3_free(message);
        if (is_busy(sqlite3_errcode(db))) return busy_error(path, doing);
        return make_error(ErrorCode::io_error, path.string() + ": " + doing + ": " + why);
    }
    return {};
}

// Rolls back unless committed.
class Transaction {
public:
    Transaction(sqlite3* db) : db_(db) {}
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    ~Transaction() {
        if (open_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    }
    void began() { open_ = true; }
    void committed() { open_ = false; }

private:
    sqlite3* db_;
    bool open_ = false;
};

} // namespace

// An XDG base directory: the variable's value, or ~/.local/<fallback>. The spec: a relative value is
// invalid and is ignored.
std::filesystem::path xdg_dir(const char* variable, const char* fallback) {
    const char* xdg = std::getenv(variable);
    if (xdg && *xdg && std::filesystem::path(xdg).is_absolute()) return xdg;
    const char* home = std::getenv("HOME");
    return std::filesystem::path(home && *home ? home : ".") / ".local" / fallback;
}

namespace {
// A database's folder: made only where the program keeps its own (the default, under
// $XDG_DATA_HOME); a --db whose folder is missing is refused rather than made (a mistyped path once
// made /nonexistent/dir as root, silently).
Result<void> check_folder(const std::filesystem::path& path) {
    const auto folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    std::error_code ec;
    if (std::filesystem::is_directory(folder, ec)) {
        if (::access(folder.c_str(), W_OK | X_OK) != 0) return make_error(ErrorCode::io_error, path.string() + ": its folder " + folder.string() + " cannot be written to");
        return {};
    }
    if (path == default_progress_path()) {
        std::filesystem::create_directories(folder, ec);
        if (ec) return make_error(ErrorCode::io_error, folder.string() + ": cannot be created: " + ec.message());
        return {};
    }
    return make_error(ErrorCode::not_found, path.string() + ": its folder " + folder.string() + " does not exist (make it, or give another --db)");
}
} // namespace

Result<void> check_progress_path(const std::filesystem::path& path) {
    if (auto regular = check_regular_path(path); !regular) return regular;
    // Everything a save will need, looked at before the work: the file, if there, is Ikebana's and
    // may be written; if not, its folder is there and may be written (a read-only or foreign database
    // was refused only after a whole demonstration had run).
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) {
        if (auto ours = check_existing(path); !ours) return ours.error();
        if (::access(path.c_str(), W_OK) != 0) return make_error(ErrorCode::io_error, path.string() + ": read-only: the session could not be stored in it");
    }
    const auto folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    if (!std::filesystem::is_directory(folder, ec) && path != default_progress_path()) {
        return make_error(ErrorCode::not_found, path.string() + ": its folder " + folder.string() + " does not exist (make it, or give another --db)");
    }
    return {};
}

std::filesystem::path default_progress_path() { return xdg_dir("XDG_DATA_HOME", "share") / "ikebana" / "progress.sqlite"; }

std::filesystem::path default_log_path() { return xdg_dir("XDG_STATE_HOME", "state") / "ikebana" / "last-session.log"; }

std::vector<FlowerOutcome> flower_outcomes(const components::FrameSnapshot& frame) {
    std::vector<FlowerOutcome> out;
    for (const auto& f : frame.flowers) out.push_back({f.species, f.insertions, f.bottom_broken, f.fallen});
    return out;
}

std::string iso_utc(std::int64_t unix_s) {
    const std::time_t t = static_cast<std::time_t>(unix_s);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return text;
}

Result<ProgressDb> ProgressDb::open(const std::filesystem::path& path) {
    if (auto regular = check_regular_path(path); !regular) return regular.error();
    std::error_code ec;
    const bool exists = std::filesystem::exists(path, ec);
    bool fresh = !exists;
    if (exists) {
        auto needs_tables = check_existing(path);
        if (!needs_tables) return needs_tables.error();
        fresh = *needs_tables;
    } else if (auto folder = check_folder(path); !folder) {
        return folder.error();
    }
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOFOLLOW, nullptr) != SQLITE_OK) {
        Error e = make_error(ErrorCode::io_error, path.string() + ": cannot be opened for writing: " + (db ? sqlite3_errmsg(db) : "out of memory"));
        sqlite3_close_v2(db);
        return e;
    }
    ProgressDb out(db, path);
    // Everything that makes the file ours, as one step: a file this open made and could not finish (a
    // full disk) is removed with whatever SQLite put beside it, not left as a 0-byte database.
    const auto set_up = [&]() -> Result<void> {
        sqlite3_busy_timeout(db, open_wait_ms);
        if (fresh) {
            // Two stations started at once on a new file both find it empty: the first to hold the write
            // lock makes the tables, and the other, let in after it, finds them made.
            if (auto r = exec(db, path, "BEGIN IMMEDIATE", "cannot be started"); !r) return r;
            int code = SQLITE_OK;
            const auto app = single_integer(db, "PRAGMA application_id", code);
            if (app && *app == application_id) {
                if (auto r = exec(db, path, "COMMIT", "cannot be started"); !r) return r;
            } else {
                char init[160];
                std::snprintf(init, sizeof init, "PRAGMA application_id = %d; PRAGMA user_version = %d;", application_id, schema_version);
                if (auto r = exec(db, path, init, "cannot be started"); !r) {
                    (void)exec(db, path, "ROLLBACK", "");
                    return r;
                }
                if (auto r = exec(db, path, schema_sql, "cannot be started"); !r) {
                    (void)exec(db, path, "ROLLBACK", "");
                    return r;
                }
                if (auto r = exec(db, path, "COMMIT", "cannot be started"); !r) return r;
            }
        }
        // A killed app loses at most the session it was writing: each commit is in the log before it
        // returns (FULL), and the log survives the process.
        // Turning the log on takes the file alone, and SQLite answers busy at once rather than call the
        // busy handler while another station has it open (two stations started on a new file: 4 runs in
        // 40 of the two-stations test failed here): tried again until the open's wait is over.
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(open_wait_ms);
        for (;;) {
            auto r = exec(db, path, "PRAGMA journal_mode = WAL", "cannot be set up");
            if (r) break;
            if (r.error().code != ErrorCode::busy || std::chrono::steady_clock::now() > until) return r;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        if (auto r = exec(db, path, "PRAGMA synchronous = FULL; PRAGMA foreign_keys = ON;", "cannot be set up"); !r) return r;
        return {};
    };
    if (auto ready = set_up(); !ready) {
        if (!exists) {
            out = ProgressDb(nullptr, path);
            for (const char* suffix : {"", "-wal", "-shm", "-journal"}) std::filesystem::remove(path.string() + suffix, ec);
        }
        return ready.error();
    }
    // Another window of the app saving at the same moment: saves run on the frame's lane, so no long
    // waits there (a save that finds the file busy is tried again: StoredSessions).
    sqlite3_busy_timeout(db, save_wait_ms);
    return out;
}

Result<ProgressDb> ProgressDb::open_read_only(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return make_error(ErrorCode::not_found, path.string() + ": no sessions yet (the file does not exist)");
    if (auto regular = check_regular_path(path); !regular) return regular.error();
    auto empty = check_existing(path);
    if (!empty) return empty.error();
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOFOLLOW, nullptr) != SQLITE_OK) {
        Error e = make_error(ErrorCode::io_error, path.string() + ": cannot be opened: " + (db ? sqlite3_errmsg(db) : "out of memory"));
        sqlite3_close_v2(db);
        return e;
    }
    if (*empty) {
        sqlite3_close_v2(db);
        return make_error(ErrorCode::not_found, path.string() + ": no sessions yet (the file is empty)");
    }
    sqlite3_busy_timeout(db, open_wait_ms);
    return ProgressDb(db, path);
}

ProgressDb::ProgressDb(ProgressDb&& other) noexcept : db_(std::exchange(other.db_, nullptr)), path_(std::move(other.path_)) {}

ProgressDb& ProgressDb::operator=(ProgressDb&& other) noexcept {
    if (this != &other) {
        if (db_) sqlite3_close_v2(db_);
        db_ = std::exchange(other.db_, nullptr);
        path_ = std::move(other.path_);
    }
    return *this;
}

void ProgressDb::set_busy_wait_ms(int ms) { sqlite3_busy_timeout(db_, ms); }

ProgressDb::~ProgressDb() {
    if (db_) sqlite3_close_v2(db_);
}

Result<void> ProgressDb::save(SessionRecord& s) {
    if (s.kind != "practice" && s.kind != "demonstration") return make_error(ErrorCode::invalid_argument, "a session's kind is practice or demonstration, not " + s.kind);
    Transaction tx(db_);
    if (auto r = exec(db_, path_, "BEGIN IMMEDIATE", "cannot save the session"); !r) return r;
    tx.began();
    const auto failed = [&](const char* what) { return db_error(path_, db_, std::string("cannot save the session (") + what + ")"); };
    std::int64_t id = s.id;
    {
        Statement row(db_, id == 0 ? "INSERT INTO sessions(lesson, trainee, kind, started_unix_s, duration_s, score, how, arrangement, recording) "
                                     "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)"
                                   : "UPDATE sessions SET lesson = ?1, trainee = ?2, kind = ?3, started_unix_s = ?4, duration_s = ?5, score = ?6, how = ?7, "
                                     "arrangement = ?8, recording = ?9 WHERE id = ?10");
        if (!row.prepared()) return failed("sessions");
        row.bind(1, s.lesson);
        row.bind(2, s.trainee);
        row.bind(3, s.kind);
        row.bind(4, s.started_unix_s);
        row.bind(5, s.duration_s);
        row.bind(6, s.result.score);
        row.bind(7, s.result.how);
        row.bind(8, arrangement_json(s.result.arrangement, -1));
        row.bind(9, s.recording);
        if (id != 0) row.bind(10, id);
        if (row.step() != SQLITE_DONE) return failed("sessions");
        if (id == 0) {
            id = sqlite3_last_insert_rowid(db_);
        } else if (sqlite3_changes(db_) != 1) {
            return make_error(ErrorCode::not_found, path_.string() + ": no session " + std::to_string(id) + " to save again");
        }
    }
    for (const char* table : {"DELETE FROM criteria WHERE session_id = ?1", "DELETE FROM rules WHERE session_id = ?1", "DELETE FROM flowers WHERE session_id = ?1"}) {
        Statement del(db_, table);
        if (!del.prepared()) return failed("old rows");
        del.bind(1, id);
        if (del.step() != SQLITE_DONE) return failed("old rows");
    }
    Statement criteria(db_, "INSERT INTO criteria VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)");
    Statement rules(db_, "INSERT INTO rules VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)");
    Statement flowers(db_, "INSERT INTO flowers VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
    if (!criteria.prepared() || !rules.prepared() || !flowers.prepared()) return failed("statements");
    std::int64_t at = 0;
    for (const auto& k : s.result.criteria) {
        if (!criteria.row(id, at++, k.stem, k.name, k.target, k.tolerance, k.measured, k.points, k.max_points, k.tip)) return failed("criteria");
    }
    at = 0;
    for (const auto& k : s.result.rules) {
        if (!rules.row(id, at++, k.name, std::int64_t{k.ok}, k.points, k.max_points, k.tip)) return failed("rules");
    }
    at = 0;
    for (const auto& k : s.flowers) {
        if (!flowers.row(id, at++, k.species, std::int64_t{k.insertions}, std::int64_t{k.broken}, std::int64_t{k.fallen})) return failed("flowers");
    }
    if (auto r = exec(db_, path_, "COMMIT", "cannot save the session"); !r) return r;
    tx.committed();
    s.id = id;
    return {};
}

Result<std::vector<SessionRecord>> ProgressDb::sessions(const SessionFilter& filter) const {
    const auto failed = [&] { return make_error(ErrorCode::parse_error, path_.string() + ": cannot be read: " + sqlite3_errmsg(db_)); };
    // One snapshot for the whole read, with a writer going on beside it.
    if (auto r = exec(db_, path_, "BEGIN", "cannot be read"); !r) return r.error();
    Transaction tx(db_);
    tx.began();
    std::vector<SessionRecord> out;
    Statement q(db_, "SELECT id, lesson, trainee, kind, started_unix_s, duration_s, score, how, arrangement, recording FROM sessions "
                     "WHERE (?1 = '' OR trainee = ?1) AND (?2 = '' OR lesson = ?2) ORDER BY started_unix_s, id");
    if (!q.prepared()) return failed();
    q.bind(1, filter.trainee);
    q.bind(2, filter.lesson);
    int rc = SQLITE_ROW;
    while ((rc = q.step()) == SQLITE_ROW) {
        SessionRecord s;
        s.id = q.integer(0);
        s.lesson = q.text(1);
        s.trainee = q.text(2);
        s.kind = q.text(3);
        s.started_unix_s = q.integer(4);
        s.duration_s = q.real(5);
        s.result.lesson = s.lesson;
        s.result.score = q.real(6);
        s.result.how = q.text(7);
        auto arrangement = parse_arrangement(q.text(8), path_.string() + ": session " + std::to_string(s.id) + "'s arrangement");
        if (!arrangement) return arrangement.error();
        s.result.arrangement = std::move(*arrangement);
        s.recording = q.bytes(9); // shown through utf8_or_replacement or terminal_text where it is shown
        out.push_back(std::move(s));
    }
    if (rc != SQLITE_DONE) return failed();
    Statement c(db_, "SELECT stem, name, target, tolerance, measured, points, max_points, tip FROM criteria WHERE session_id = ?1 ORDER BY position");
    Statement r(db_, "SELECT name, ok, points, max_points, tip FROM rules WHERE session_id = ?1 ORDER BY position");
    Statement f(db_, "SELECT species, insertions, broken, fallen FROM flowers WHERE session_id = ?1 ORDER BY position");
    if (!c.prepared() || !r.prepared() || !f.prepared()) return failed();
    for (auto& s : out) {
        c.bind(1, s.id);
        while ((rc = c.step()) == SQLITE_ROW) {
            Criterion k;
            k.stem = c.text(0);
            k.name = c.text(1);
            k.target = c.real(2);
            k.tolerance = c.real(3);
            if (!c.null(4)) k.measured = c.real(4);
            k.points = c.real(5);
            k.max_points = c.real(6);
            k.tip = c.text(7);
            s.result.criteria.push_back(std::move(k));
        }
        if (rc != SQLITE_DONE) return failed();
        c.reset();
        r.bind(1, s.id);
        while ((rc = r.step()) == SQLITE_ROW) {
            RuleResult k;
            k.name = r.text(0);
            k.ok = r.integer(1) != 0;
            k.points = r.real(2);
            k.max_points = r.real(3);
            k.tip = r.text(4);
            s.result.rules.push_back(std::move(k));
        }
        if (rc != SQLITE_DONE) return failed();
        r.reset();
        f.bind(1, s.id);
        while ((rc = f.step()) == SQLITE_ROW) {
            FlowerOutcome k;
            k.species = f.text(0);
            k.insertions = static_cast<std::uint32_t>(std::clamp<std::int64_t>(f.integer(1), 0, UINT32_MAX));
            k.broken = f.integer(2) != 0;
            k.fallen = f.integer(3) != 0;
            s.flowers.push_back(std::move(k));
        }
        if (rc != SQLITE_DONE) return failed();
        f.reset();
    }
    return out;
}

Result<std::optional<std::string>> ProgressDb::setting(const std::string& key) const {
    Statement q(db_, "SELECT value FROM settings WHERE key = ?1");
    if (!q.prepared()) return make_error(ErrorCode::parse_error, path_.string() + ": cannot be read: " + sqlite3_errmsg(db_));
    q.bind(1, key);
    const int rc = q.step();
    if (rc == SQLITE_ROW) return std::optional<std::string>{q.text(0)};
    if (rc == SQLITE_DONE) return std::optional<std::string>{};
    return make_error(ErrorCode::parse_error, path_.string() + ": cannot be read: " + sqlite3_errmsg(db_));
}

Result<void> ProgressDb::set_setting(const std::string& key, const std::string& value) {
    Statement q(db_, "INSERT INTO settings(key, value) VALUES (?1, ?2) ON CONFLICT(key) DO UPDATE SET value = excluded.value");
    if (!q.prepared()) return db_error(path_, db_, "cannot remember " + key);
    q.bind(1, key);
    q.bind(2, value);
    if (q.step() != SQLITE_DONE) return db_error(path_, db_, "cannot remember " + key);
    return {};
}

} // namespace ikebana::game
