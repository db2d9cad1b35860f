#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <latch>
#include <set>
#include <thread>
#include <string>

#include <sqlite3.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "engine/sched/clocks.hpp"
#include "game/app/stored_sessions.hpp"
#include "game/lesson/lesson.hpp"
#include "game/progress/progress_db.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/world/world.hpp"
#include "game/progress/progress_plot.hpp"
#include "systems/presentation/frame_channel.hpp"
#include "../haptics/scripted_hands.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {

// A folder of its own per test (ctest runs them side by side).
std::filesystem::path fresh_dir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const auto dir = std::filesystem::temp_directory_path() / (std::string("ikebana-progress-") + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

std::string bytes_of(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

SessionRecord session(const std::string& lesson, const std::string& trainee, double score, std::int64_t started) {
    SessionRecord s;
    s.lesson = lesson;
    s.trainee = trainee;
    s.started_unix_s = started;
    s.duration_s = 312.5;
    s.result.lesson = lesson;
    s.result.score = score;
    s.result.how = "points per band";
    Criterion tilt;
    tilt.stem = "shin";
    tilt.name = "tilt_deg";
    tilt.target = 15.0;
    tilt.tolerance = 10.0;
    tilt.measured = 48.0;
    tilt.points = 16.0;
    tilt.max_points = 30.0;
    tilt.tip = "shin: 48 deg from vertical, the form wants 15 deg +-10: raise it toward upright";
    Criterion length = tilt;
    length.name = "length_mm";
    length.measured.reset(); // no stem played the role
    length.points = 0.0;
    s.result.criteria = {tilt, length};
    s.result.rules = {{"odd_main_stems", true, 4.0, 4.0, "3 main stems stand"}, {"no_crossing", false, 0.0, 4.0, "soe crosses hikae"}};
    ArrangementStem stem;
    stem.role = "shin";
    stem.species = "willow_branch";
    stem.base_m = {0.01, -0.02};
    stem.length_m = 0.42;
    stem.tilt_rad = 0.8;
    s.result.arrangement.stems = {stem};
    s.flowers = {{"willow_branch", 3, false, false}, {"cherry_branch", 7, true, true}};
    s.recording = "/somewhere/session-1";
    return s;
}

} // namespace

TEST(ProgressDb, ASessionIsReadBackWithItsCriteriaRulesFlowersAndArrangement) {
    const auto path = fresh_dir() / "deeper" / "progress.sqlite";
    {
        // A folder that is not there is not made (a mistyped --db made folders as root): refused.
        auto refused = ProgressDb::open(path);
        ASSERT_FALSE(refused);
        EXPECT_NE(refused.error().message.find("deeper does not exist (make it, or give another --db)"), std::string::npos) << refused.error().message;
        EXPECT_FALSE(std::filesystem::exists(path.parent_path()));
        std::filesystem::create_directories(path.parent_path());
        auto db = ProgressDb::open(path);
        ASSERT_TRUE(db) << db.error().message;
        auto s = session("sogetsu_basic_upright", "mika", 72.5, 1'700'000'000);
        ASSERT_TRUE(db->save(s));
        EXPECT_EQ(s.id, 1);
    }
    auto db = ProgressDb::open_read_only(path);
    ASSERT_TRUE(db) << db.error().message;
    auto all = db->sessions();
    ASSERT_TRUE(all) << all.error().message;
    ASSERT_EQ(all->size(), 1u);
    const auto& s = all->front();
    EXPECT_EQ(s.lesson, "sogetsu_basic_upright");
    EXPECT_EQ(s.trainee, "mika");
    EXPECT_EQ(s.kind, "practice");
    EXPECT_EQ(s.started_unix_s, 1'700'000'000);
    EXPECT_DOUBLE_EQ(s.duration_s, 312.5);
    EXPECT_DOUBLE_EQ(s.result.score, 72.5);
    ASSERT_EQ(s.result.criteria.size(), 2u);
    EXPECT_EQ(s.result.criteria[0].name, "tilt_deg");
    ASSERT_TRUE(s.result.criteria[0].measured);
    EXPECT_DOUBLE_EQ(*s.result.criteria[0].measured, 48.0);
    EXPECT_FALSE(s.result.criteria[1].measured) << "a role nobody played stays unmeasured, not 0";
    ASSERT_EQ(s.result.rules.size(), 2u);
    EXPECT_FALSE(s.result.rules[1].ok);
    ASSERT_EQ(s.flowers.size(), 2u);
    EXPECT_EQ(s.flowers[1].insertions, 7u);
    EXPECT_TRUE(s.flowers[1].broken);
    EXPECT_TRUE(s.flowers[1].fallen);
    ASSERT_EQ(s.result.arrangement.stems.size(), 1u);
    EXPECT_NEAR(s.result.arrangement.stems[0].length_m, 0.42, 1e-3);
    EXPECT_EQ(s.recording, "/somewhere/session-1");
    EXPECT_EQ(iso_utc(s.started_unix_s), "2023-11-14T22:13:20Z");
}

TEST(ProgressDb, ASessionScoredAgainIsReplacedNotStoredTwice) {
    const auto path = fresh_dir() / "progress.sqlite";
    auto db = ProgressDb::open(path);
    ASSERT_TRUE(db) << db.error().message;
    auto s = session("sogetsu_basic_upright", "mika", 40.0, 100);
    ASSERT_TRUE(db->save(s));
    s.result.score = 91.0;
    s.result.criteria.pop_back();
    s.flowers.pop_back();
    ASSERT_TRUE(db->save(s));
    auto all = db->sessions();
    ASSERT_TRUE(all);
    ASSERT_EQ(all->size(), 1u);
    EXPECT_DOUBLE_EQ(all->front().result.score, 91.0);
    EXPECT_EQ(all->front().result.criteria.size(), 1u) << "the first Enter's criteria are gone with it";
    EXPECT_EQ(all->front().flowers.size(), 1u);
}

TEST(ProgressDb, SessionsAreFilteredByTraineeAndLessonOldestFirst) {
    const auto path = fresh_dir() / "progress.sqlite";
    auto db = ProgressDb::open(path);
    ASSERT_TRUE(db);
    auto late = session("ohara_rising_form", "mika", 80.0, 300);
    auto early = session("ohara_rising_form", "mika", 60.0, 100);
    auto other = session("sogetsu_basic_upright", "ren", 50.0, 200);
    other.kind = "demonstration";
    for (auto* s : {&late, &early, &other}) ASSERT_TRUE(db->save(*s));
    auto mika = db->sessions({"mika", ""});
    ASSERT_TRUE(mika);
    ASSERT_EQ(mika->size(), 2u);
    EXPECT_DOUBLE_EQ((*mika)[0].result.score, 60.0) << "oldest first, whatever order they were stored in";
    auto upright = db->sessions({"", "sogetsu_basic_upright"});
    ASSERT_TRUE(upright);
    ASSERT_EQ(upright->size(), 1u);
    EXPECT_EQ(upright->front().kind, "demonstration");
    SessionRecord odd = early;
    odd.id = 0;
    odd.kind = "exam";
    EXPECT_FALSE(db->save(odd));
}

TEST(ProgressDb, TheTraineesNameIsRemembered) {
    const auto path = fresh_dir() / "progress.sqlite";
    {
        auto db = ProgressDb::open(path);
        ASSERT_TRUE(db);
        auto none = db->setting("trainee");
        ASSERT_TRUE(none);
        EXPECT_FALSE(*none);
        ASSERT_TRUE(db->set_setting("trainee", "mika"));
        ASSERT_TRUE(db->set_setting("trainee", "Mika Sato"));
    }
    auto db = ProgressDb::open(path);
    ASSERT_TRUE(db);
    auto name = db->setting("trainee");
    ASSERT_TRUE(name && *name);
    EXPECT_EQ(**name, "Mika Sato");
}

// The app killed while it writes: every session stored before is whole, and none is half there.
TEST(ProgressDb, AWriterKilledMidSessionLosesNoEarlierSession) {
    const auto path = fresh_dir() / "progress.sqlite";
    {
        auto db = ProgressDb::open(path);
        ASSERT_TRUE(db);
        auto first = session("sogetsu_basic_upright", "mika", 70.0, 1);
        ASSERT_TRUE(db->save(first));
    }
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        auto db = ProgressDb::open(path);
        if (!db) _exit(3);
        for (std::int64_t i = 2;; ++i) {
            auto s = session("sogetsu_basic_upright", "mika", 50.0, i);
            // Many criteria: a transaction long enough to be cut in its middle.
            for (int k = 0; k < 200; ++k) s.result.criteria.push_back(s.result.criteria.front());
            if (!db->save(s)) _exit(4);
        }
    }
    usleep(400'000);
    kill(child, SIGKILL);
    int status = 0;
    waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the writer stopped by itself, exit " << WEXITSTATUS(status);
    auto db = ProgressDb::open(path);
    ASSERT_TRUE(db) << db.error().message;
    auto all = db->sessions();
    ASSERT_TRUE(all) << all.error().message;
    ASSERT_GE(all->size(), 2u) << "the killed writer stored nothing in 0.4 s";
    EXPECT_DOUBLE_EQ(all->front().result.score, 70.0);
    EXPECT_EQ(all->front().result.criteria.size(), 2u);
    for (std::size_t i = 1; i < all->size(); ++i) {
        EXPECT_EQ((*all)[i].result.criteria.size(), 202u) << "session " << (*all)[i].id << " is half stored";
        EXPECT_EQ((*all)[i].flowers.size(), 2u);
    }
    // And the database takes the next session.
    auto next = session("ohara_rising_form", "mika", 99.0, 1'000'000);
    EXPECT_TRUE(db->save(next));
}

TEST(ProgressDb, AFileThatIsNotADatabaseIsReportedAndLeftAsItIs) {
    const auto path = fresh_dir() / "progress.sqlite";
    { std::ofstream(path) << "my notes on shin and soe\n"; }
    const auto before = bytes_of(path);
    for (const auto& opened : {ProgressDb::open(path), ProgressDb::open_read_only(path)}) {
        ASSERT_FALSE(opened);
        EXPECT_EQ(opened.error().message,
                  path.string() + ": not an Ikebana progress database (not an SQLite file); it is left as it is (move it aside to start a new record)");
    }
    EXPECT_EQ(bytes_of(path), before);
    EXPECT_FALSE(std::filesystem::exists(path.string() + "-wal"));
}

TEST(ProgressDb, ADamagedDatabaseIsReportedAndLeftAsItIs) {
    const auto path = fresh_dir() / "progress.sqlite";
    {
        auto db = ProgressDb::open(path);
        ASSERT_TRUE(db);
        for (int i = 0; i < 20; ++i) {
            auto s = session("sogetsu_basic_upright", "mika", 50.0 + i, i);
            ASSERT_TRUE(db->save(s));
        }
    }
    // Bytes overwritten inside the tables' pages (past the header and the schema page).
    std::string bytes = bytes_of(path);
    ASSERT_GT(bytes.size(), 4096u * 4);
    for (std::size_t i = 4096 * 2; i < bytes.size(); i += 7) bytes[i] = static_cast<char>(0xA5);
    { std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes; }
    const auto before = bytes_of(path);
    auto opened = ProgressDb::open(path);
    ASSERT_FALSE(opened);
    EXPECT_NE(opened.error().message.find(path.string() + ": damaged ("), std::string::npos) << opened.error().message;
    EXPECT_NE(opened.error().message.find("it is left as it is"), std::string::npos);
    EXPECT_EQ(bytes_of(path), before) << "a damaged record is never written to";
}

// An index that misses rows of its table passes SQLite's quick_check; a session saved into such a
// file was read back without its criteria (a fuzzer's file). The index's page is put back as it was
// before any session: the full check at open names the damage and nothing is written.
TEST(ProgressDb, AnIndexMissingRowsOfItsTableIsDamage) {
    const auto path = fresh_dir() / "progress.sqlite";
    { ASSERT_TRUE(ProgressDb::open(path)); }
    const std::string empty = bytes_of(path);
    {
        auto db = ProgressDb::open(path);
        ASSERT_TRUE(db);
        for (int i = 0; i < 3; ++i) {
            auto s = session("sogetsu_basic_upright", "mika", 50.0 + i, i);
            ASSERT_TRUE(db->save(s));
        }
    }
    long long root = 0, page = 0;
    {
        sqlite3* raw = nullptr;
        ASSERT_EQ(sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
        sqlite3_stmt* st = nullptr;
        ASSERT_EQ(sqlite3_prepare_v2(raw, "SELECT rootpage FROM sqlite_schema WHERE name = 'criteria_of_session'", -1, &st, nullptr), SQLITE_OK);
        ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
        root = sqlite3_column_int64(st, 0);
        sqlite3_finalize(st);
        ASSERT_EQ(sqlite3_prepare_v2(raw, "PRAGMA page_size", -1, &st, nullptr), SQLITE_OK);
        ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
        page = sqlite3_column_int64(st, 0);
        sqlite3_finalize(st);
        sqlite3_close(raw);
    }
    std::string bytes = bytes_of(path);
    const auto at = static_cast<std::size_t>((root - 1) * page);
    ASSERT_LE(at + static_cast<std::size_t>(page), empty.size()) << "the index's page existed before any session";
    bytes.replace(at, static_cast<std::size_t>(page), empty, at, static_cast<std::size_t>(page));
    { std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes; }
    const auto before = bytes_of(path);
    auto opened = ProgressDb::open(path);
    ASSERT_FALSE(opened);
    EXPECT_NE(opened.error().message.find(path.string() + ": damaged (row "), std::string::npos) << opened.error().message;
    EXPECT_NE(opened.error().message.find("missing from index criteria_of_session"), std::string::npos) << opened.error().message;
    EXPECT_EQ(bytes_of(path), before) << "a damaged record is never written to";
    EXPECT_FALSE(ProgressDb::open_read_only(path)) << "nor read as if whole";
}

TEST(ProgressDb, AnotherProgramsDatabaseOrANewerOneIsLeftAlone) {
    const auto dir = fresh_dir();
    const auto foreign = dir / "foreign.sqlite";
    const auto newer = dir / "newer.sqlite";
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(foreign.c_str(), &raw), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(raw, "CREATE TABLE recipes(name TEXT)", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(raw);
    {
        auto db = ProgressDb::open(newer);
        ASSERT_TRUE(db);
    }
    ASSERT_EQ(sqlite3_open(newer.c_str(), &raw), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(raw, "PRAGMA journal_mode = DELETE; PRAGMA user_version = 7", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(raw);
    const auto foreign_bytes = bytes_of(foreign);
    const auto newer_bytes = bytes_of(newer);
    auto a = ProgressDb::open(foreign);
    ASSERT_FALSE(a);
    EXPECT_EQ(a.error().message, foreign.string() + ": an SQLite database of another program (application id 0x00000000, not Ikebana's); it is left as it is "
                                                    "(move it aside to start a new record)");
    auto b = ProgressDb::open(newer);
    ASSERT_FALSE(b);
    EXPECT_NE(b.error().message.find("written by a newer Ikebana (its schema is version 7, this one reads 1)"), std::string::npos) << b.error().message;
    EXPECT_EQ(bytes_of(foreign), foreign_bytes);
    EXPECT_EQ(bytes_of(newer), newer_bytes);
}

TEST(ProgressDb, ASymbolicLinkWhereTheDatabaseGoesIsRefused) {
    const auto dir = fresh_dir();
    // Even to a good database of ours (only NOFOLLOW refuses that one), and a dangling one is not followed to make a file.
    {
        auto real = ProgressDb::open(dir / "real.sqlite");
        ASSERT_TRUE(real);
        auto s = session("sogetsu_basic_upright", "aiko", 80.0, 1000);
        ASSERT_TRUE(real->save(s));
    }
    const auto real_bytes = bytes_of(dir / "real.sqlite");
    std::filesystem::create_symlink(dir / "real.sqlite", dir / "progress.sqlite");
    std::filesystem::create_symlink(dir / "nowhere.sqlite", dir / "dangling.sqlite");
    auto linked = ProgressDb::open(dir / "progress.sqlite");
    ASSERT_FALSE(linked);
    EXPECT_NE(linked.error().message.find(dir.string() + "/progress.sqlite"), std::string::npos) << linked.error().message;
    auto reader = ProgressDb::open_read_only(dir / "progress.sqlite");
    EXPECT_FALSE(reader);
    EXPECT_FALSE(ProgressDb::open(dir / "dangling.sqlite"));
    EXPECT_EQ(bytes_of(dir / "real.sqlite"), real_bytes);
    EXPECT_FALSE(std::filesystem::exists(dir / "nowhere.sqlite"));
}

TEST(ProgressDb, OurHeaderOnOtherTablesIsDamageAndLeftAlone) {
    const auto path = fresh_dir() / "progress.sqlite";
    {
        auto db = ProgressDb::open(path);
        ASSERT_TRUE(db);
    }
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(raw, "PRAGMA journal_mode = DELETE; DROP TABLE flowers; CREATE TABLE recipes(name TEXT)", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(raw);
    const auto before = bytes_of(path);
    auto db = ProgressDb::open(path);
    ASSERT_FALSE(db);
    EXPECT_EQ(db.error().message, path.string() + ": damaged (Ikebana's header, but not its tables); it is left as it is (move it aside to start a new record)");
    EXPECT_EQ(bytes_of(path), before);
}

TEST(ProgressDb, AMissingFileIsNoSessionsYetForAReaderAndIsNotCreated) {
    const auto path = fresh_dir() / "progress.sqlite";
    auto db = ProgressDb::open_read_only(path);
    ASSERT_FALSE(db);
    EXPECT_EQ(db.error().code, ErrorCode::not_found);
    EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(ProgressDb, TheDefaultPlaceFollowsXdgDataHome) {
    const char* was = std::getenv("XDG_DATA_HOME");
    const std::string kept = was ? was : "";
    const char* home = std::getenv("HOME");
    const std::string kept_home = home ? home : "";
    setenv("XDG_DATA_HOME", "/data/mika", 1);
    EXPECT_EQ(default_progress_path(), std::filesystem::path("/data/mika/ikebana/progress.sqlite"));
    setenv("XDG_DATA_HOME", "relative/is/ignored", 1);
    setenv("HOME", "/home/mika", 1);
    EXPECT_EQ(default_progress_path(), std::filesystem::path("/home/mika/.local/share/ikebana/progress.sqlite"));
    if (was) setenv("XDG_DATA_HOME", kept.c_str(), 1);
    else unsetenv("XDG_DATA_HOME");
    if (home) setenv("HOME", kept_home.c_str(), 1);
    else unsetenv("HOME");
}

TEST(ProgressPlot, IsAPngOrAnSvgWithAPanelPerLesson) {
    std::vector<SessionRecord> sessions{session("sogetsu_basic_upright", "mika", 40.0, 100), session("sogetsu_basic_upright", "mika", 85.0, 200),
                                        session("ohara_rising_form", "mika", 70.0, 300)};
    auto png = render_progress_plot(sessions, "Ikebana progress: mika", PlotFormat::png);
    ASSERT_TRUE(png) << png.error().message;
    ASSERT_GT(png->size(), 24u);
    EXPECT_EQ(png->substr(1, 3), "PNG");
    // Width and height from the IHDR chunk: 1000 wide, a title and two panels high.
    const auto be32 = [&](std::size_t at) {
        return (static_cast<std::uint32_t>(static_cast<unsigned char>((*png)[at])) << 24) | (static_cast<std::uint32_t>(static_cast<unsigned char>((*png)[at + 1])) << 16) |
               (static_cast<std::uint32_t>(static_cast<unsigned char>((*png)[at + 2])) << 8) | static_cast<unsigned char>((*png)[at + 3]);
    };
    EXPECT_EQ(be32(16), 1000u);
    EXPECT_EQ(be32(20), 56u + 2u * 320u);
    auto svg = render_progress_plot(sessions, "Ikebana progress: mika", PlotFormat::svg);
    ASSERT_TRUE(svg);
    EXPECT_NE(svg->find("<svg"), std::string::npos);
    EXPECT_FALSE(plot_format_of("progress.pdf"));
    EXPECT_EQ(plot_format_of("progress.PNG").value(), PlotFormat::png);
}

// Two windows on one database that begin a session of one lesson in the same second (CI's two window
// lessons side by side; two trainees sharing a machine) each get a recording folder of their own: both
// once took "<second>-<lesson>" after both saw it free, and wrote each other's right.csv to pieces.
TEST(StoredSessions, TwoSessionsBegunInOneSecondRecordIntoFoldersOfTheirOwn) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana-stored-sessions-test";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    game::TraineeAppOptions options;
    options.progress_db = (dir / "progress.sqlite").string();
    auto lesson = game::load_lesson("sogetsu_basic_upright");
    ASSERT_TRUE(lesson.ok()) << lesson.error().message;
    auto scene = game::scene_for_lesson(*lesson);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    for (int round = 0; round < 8; ++round) {
        auto one = game::World::create(*scene);
        auto two = game::World::create(*scene);
        ASSERT_TRUE(one.ok() && two.ok());
        game::StoredSessions first(options), second(options);
        (void)first.open(false, &*lesson);
        (void)second.open(false, &*lesson);
        // Both begin at once, as two processes would.
        std::latch go(2);
        std::thread other([&] {
            go.arrive_and_wait();
            second.begin(**two, &*lesson);
        });
        go.arrive_and_wait();
        first.begin(**one, &*lesson);
        other.join();
        ASSERT_NE(first.recorder(), nullptr);
        ASSERT_NE(second.recorder(), nullptr);
        EXPECT_NE(first.recorder()->folder(), second.recorder()->folder()) << "round " << round;
        EXPECT_TRUE(first.finish(**one, &*lesson));
        EXPECT_TRUE(second.finish(**two, &*lesson));
    }
    std::filesystem::remove_all(dir);
}

namespace {
// Another station's connection holding the write lock (as one saving a session does) until released.
struct WriteLock {
    sqlite3* db = nullptr;
    explicit WriteLock(const std::filesystem::path& path) {
        EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
        EXPECT_EQ(sqlite3_exec(db, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
    }
    void release() {
        if (!db) return;
        sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr);
        sqlite3_close(db);
        db = nullptr;
    }
    ~WriteLock() { release(); }
};
} // namespace

// Two stations on one database: a save that finds the other writing waits for it, and one that
// waits in vain is told the file is busy (ErrorCode::busy), never that it is damaged; once the other
// is done, the same session is stored.
TEST(ProgressDb, AFileAnotherStationIsWritingIsBusyNotDamaged) {
    const auto path = fresh_dir() / "progress.sqlite";
    auto db = ProgressDb::open(path);
    ASSERT_TRUE(db) << db.error().message;
    {
        WriteLock other(path);
        auto s = session("sogetsu_basic_upright", "mika", 70.0, 1);
        auto saved = db->save(s);
        ASSERT_FALSE(saved);
        EXPECT_EQ(saved.error().code, ErrorCode::busy);
        EXPECT_NE(saved.error().message.find("busy (another program, perhaps another Ikebana, is writing it)"), std::string::npos) << saved.error().message;
        EXPECT_EQ(saved.error().message.find("damaged"), std::string::npos);
        other.release();
        EXPECT_TRUE(db->save(s));
    }
    // Held for half a second while a save waits up to two: stored, after the other.
    db->set_busy_wait_ms(2000);
    WriteLock other(path);
    std::thread releaser([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        other.release();
    });
    auto later = session("sogetsu_basic_upright", "mika", 80.0, 2);
    EXPECT_TRUE(db->save(later));
    releaser.join();
    auto all = db->sessions();
    ASSERT_TRUE(all);
    EXPECT_EQ(all->size(), 2u);
}

// Two apps started at once on one new file (3 of 7 tries once said "damaged (database is locked)"
// and stored nothing all session): both open it and every session of each is stored. Eight rounds of
// two processes, each saving five sessions.
TEST(ProgressDb, TwoStationsStartedAtOnceOnANewFileBothStoreEverySession) {
    const auto dir = fresh_dir();
    for (int round = 0; round < 8; ++round) {
        const auto path = dir / ("progress-" + std::to_string(round) + ".sqlite");
        pid_t children[2];
        for (auto& child : children) {
            child = fork();
            ASSERT_GE(child, 0);
            if (child == 0) {
                auto db = ProgressDb::open(path);
                if (!db) _exit(db.error().code == ErrorCode::busy ? 5 : 3);
                for (std::int64_t i = 0; i < 5; ++i) {
                    auto s = session("sogetsu_basic_upright", "station " + std::to_string(getpid()), 50.0, i);
                    db->set_busy_wait_ms(5000);
                    if (!db->save(s)) _exit(4);
                }
                _exit(0);
            }
        }
        for (const pid_t child : children) {
            int status = 0;
            waitpid(child, &status, 0);
            ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "round " << round << ": a station failed, exit " << WEXITSTATUS(status);
        }
        auto db = ProgressDb::open_read_only(path);
        ASSERT_TRUE(db) << db.error().message;
        auto all = db->sessions();
        ASSERT_TRUE(all) << all.error().message;
        EXPECT_EQ(all->size(), 10u) << "round " << round;
    }
}

// Killed while it made the tables of a new file (before the write-ahead log is on), a writer leaves a
// hot journal. Read through a read-only connection, the file was "damaged (attempt to write a readonly
// database)" (the kill test, once, killed 30 ms in); opened now, the half-made file is put back as it
// was (empty) and made anew.
TEST(ProgressDb, AWriterKilledWhileMakingANewFileLeavesOneThatOpens) {
    const auto path = fresh_dir() / "progress.sqlite";
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        sqlite3* raw = nullptr;
        if (sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) _exit(3);
        // A tiny cache: the transaction's pages go to the file before its commit.
        if (sqlite3_exec(raw, "PRAGMA cache_size = 1; BEGIN; CREATE TABLE scratch(x); WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 20000) "
                              "INSERT INTO scratch SELECT randomblob(200) FROM n;",
                         nullptr, nullptr, nullptr) != SQLITE_OK)
            _exit(4);
        raise(SIGKILL); // before COMMIT
        _exit(5);
    }
    int status = 0;
    waitpid(child, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit " << WEXITSTATUS(status);
    ASSERT_TRUE(std::filesystem::exists(path.string() + "-journal")) << "a hot journal left behind";
    auto db = ProgressDb::open(path);
    ASSERT_TRUE(db) << db.error().message;
    auto all = db->sessions();
    ASSERT_TRUE(all) << all.error().message;
    EXPECT_TRUE(all->empty());
    auto first = session("sogetsu_basic_upright", "mika", 70.0, 1);
    EXPECT_TRUE(db->save(first));
}

// The app killed mid-session twenty times, at moments spread over its saves: after each kill the
// database opens whole (integrity_check, in open) and every session the killed writer had been told
// was stored is there, whole.
TEST(ProgressDb, KilledTwentyTimesMidSessionTheDatabaseStaysWholeAndNoStoredSessionIsLost) {
    const auto path = fresh_dir() / "progress.sqlite";
    std::set<std::int64_t> told;
    for (int kill_no = 0; kill_no < 20; ++kill_no) {
        int pipe_fd[2];
        ASSERT_EQ(pipe(pipe_fd), 0);
        const pid_t child = fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            close(pipe_fd[0]);
            auto db = ProgressDb::open(path);
            if (!db) _exit(3);
            for (std::int64_t i = 0;; ++i) {
                auto s = session("sogetsu_basic_upright", "mika", 50.0, i);
                for (int k = 0; k < 100; ++k) s.result.criteria.push_back(s.result.criteria.front());
                if (!db->save(s)) _exit(4);
                // Told only after save() returned: this one is stored.
                if (write(pipe_fd[1], &s.id, sizeof s.id) != static_cast<ssize_t>(sizeof s.id)) _exit(5);
            }
        }
        close(pipe_fd[1]);
        usleep(static_cast<useconds_t>(30'000 + 17'000 * kill_no)); // 30-350 ms: before, between and in saves
        kill(child, SIGKILL);
        int status = 0;
        waitpid(child, &status, 0);
        ASSERT_TRUE(WIFSIGNALED(status)) << "kill " << kill_no << ": the writer stopped by itself, exit " << WEXITSTATUS(status);
        std::int64_t id = 0;
        while (read(pipe_fd[0], &id, sizeof id) == static_cast<ssize_t>(sizeof id)) told.insert(id);
        close(pipe_fd[0]);
        auto db = ProgressDb::open(path);
        ASSERT_TRUE(db) << "kill " << kill_no << ": " << db.error().message;
        auto all = db->sessions();
        ASSERT_TRUE(all) << all.error().message;
        std::set<std::int64_t> stored;
        for (const auto& s : *all) {
            stored.insert(s.id);
            EXPECT_EQ(s.result.criteria.size(), 102u) << "kill " << kill_no << ": session " << s.id << " is half stored";
        }
        for (const auto t : told) EXPECT_TRUE(stored.contains(t)) << "kill " << kill_no << ": session " << t << " was stored and is lost";
    }
    EXPECT_GT(told.size(), 20u) << "the writers stored little: the kills did not fall among saves";
}

// The database's path gets every input path's checks: a FIFO is refused at once (it hung), a device
// is refused (/dev/zero read as no sessions, and got a journal beside it), with the path in the message.
TEST(ProgressDb, AFifoOrADeviceWhereTheDatabaseGoesIsRefusedWithoutWaiting) {
    const auto dir = fresh_dir();
    const auto fifo = dir / "f.db";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    auto writer = ProgressDb::open(fifo);
    ASSERT_FALSE(writer);
    EXPECT_EQ(writer.error().message, fifo.string() + ": a FIFO, not a progress database");
    auto reader = ProgressDb::open_read_only(fifo);
    ASSERT_FALSE(reader);
    EXPECT_EQ(reader.error().message, fifo.string() + ": a FIFO, not a progress database");
    auto zero = ProgressDb::open_read_only("/dev/zero");
    ASSERT_FALSE(zero);
    EXPECT_EQ(zero.error().message, "/dev/zero: a device or socket, not a progress database");
    EXPECT_FALSE(ProgressDb::open("/dev/zero"));
    EXPECT_FALSE(std::filesystem::exists("/dev/zero-journal"));
    EXPECT_FALSE(std::filesystem::exists("/dev/zero-wal"));
}

// Text another program wrote into our tables (SQLite does not check UTF-8, and integrity_check passes)
// is read with U+FFFD where a byte is not UTF-8: the history still reads.
TEST(ProgressDb, TextThatIsNotUtf8InACellIsReadWithReplacementCharacters) {
    const auto path = fresh_dir() / "progress.sqlite";
    {
        auto db = ProgressDb::open(path);
        ASSERT_TRUE(db);
        auto s = session("sogetsu_basic_upright", "Zoe", 70.0, 1);
        ASSERT_TRUE(db->save(s));
    }
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(raw, "UPDATE sessions SET trainee = CAST(X'5A6FEB' AS TEXT)", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(raw);
    auto db = ProgressDb::open_read_only(path);
    ASSERT_TRUE(db) << db.error().message;
    auto all = db->sessions();
    ASSERT_TRUE(all) << all.error().message;
    ASSERT_EQ(all->size(), 1u);
    EXPECT_EQ(all->front().trainee, "Zo\xEF\xBF\xBD");
}

// The window's sessions, as StoredSessions sees them: mika's, in Sogetsu Basic Upright, its database in `dir`.
struct WindowBench {
    game::TraineeAppOptions options;
    LessonDef lesson;
    std::unique_ptr<game::World> world;
};
void window_bench(const std::filesystem::path& dir, WindowBench& out) {
    out.options.progress_db = (dir / "progress.sqlite").string();
    out.options.trainee = "mika";
    auto lesson = game::load_lesson("sogetsu_basic_upright");
    ASSERT_TRUE(lesson.ok()) << lesson.error().message;
    out.lesson = *lesson;
    auto scene = game::scene_for_lesson(out.lesson);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    auto world = game::World::create(*scene);
    ASSERT_TRUE(world.ok());
    out.world = std::move(world).value();
}

// A session scored while another station holds the database is kept, not lost: the HUD says it is
// not stored yet, and it is stored once the other is done (here when the window closes).
TEST(StoredSessions, ASessionScoredWhileTheDatabaseIsBusyIsKeptAndStoredLater) {
    const auto dir = fresh_dir();
    WindowBench bench;
    window_bench(dir, bench);
    ASSERT_TRUE(bench.world);
    auto& options = bench.options;
    auto* lesson = &bench.lesson;
    auto* world = &bench.world;
    game::StoredSessions stored(options);
    (void)stored.open(false, &*lesson);
    stored.begin(**world, &*lesson);
    components::HudInfo hud;
    FormScore score = session("sogetsu_basic_upright", "mika", 77.0, 1).result;
    {
        WriteLock other(dir / "progress.sqlite");
        stored.store(score, components::FrameSnapshot{}, hud);
    }
    ASSERT_FALSE(hud.result.empty());
    EXPECT_EQ(hud.result.back(), "not stored yet: the database is busy (kept)");
    EXPECT_TRUE(stored.finish(**world, &*lesson));
    stored.store_pending_at_exit();
    auto db = ProgressDb::open_read_only(dir / "progress.sqlite");
    ASSERT_TRUE(db) << db.error().message;
    auto all = db->sessions();
    ASSERT_TRUE(all);
    ASSERT_EQ(all->size(), 1u);
    EXPECT_DOUBLE_EQ(all->front().result.score, 77.0);
    EXPECT_EQ(all->front().trainee, "mika");
}

// Issue 41: `history --plot` with no trainee joined everyone's sessions and the demonstrations on one
// line. A panel per trainee and lesson, the demonstrations in their own, headed by the lesson's title.
TEST(ProgressPlot, EachTraineeAndTheDemonstrationsHaveTheirOwnPanelHeadedByTheLessonsTitle) {
    std::vector<SessionRecord> sessions(5);
    const char* who[] = {"Aiko", "Ben", "teacher", "Aiko", "Aiko"};
    const char* lesson[] = {"sogetsu_basic_upright", "sogetsu_basic_upright", "sogetsu_basic_upright", "sogetsu_basic_upright", "ohara_rising_form"};
    for (std::size_t i = 0; i < sessions.size(); ++i) {
        sessions[i].trainee = who[i];
        sessions[i].lesson = lesson[i];
        sessions[i].kind = i == 2 ? "demonstration" : "practice";
        sessions[i].started_unix_s = 1'790'000'000 + static_cast<std::int64_t>(i) * 3600;
        sessions[i].result.score = 50.0 + static_cast<double>(i);
    }
    const auto panels = plot_panels(sessions);
    ASSERT_EQ(panels.size(), 4u);
    EXPECT_EQ(panels[0].heading, "Aiko: Sogetsu: Basic Upright Style (moribana)");
    ASSERT_EQ(panels[0].sessions.size(), 2u);
    EXPECT_DOUBLE_EQ(panels[0].sessions[1]->result.score, 53.0);
    EXPECT_EQ(panels[1].heading, "Ben: Sogetsu: Basic Upright Style (moribana)");
    EXPECT_EQ(panels[2].heading, "demonstrations: Sogetsu: Basic Upright Style (moribana)");
    EXPECT_EQ(panels[3].heading, "Aiko: Ohara: Rising Form (moribana)");
    auto png = render_progress_plot(sessions, "Ikebana progress: everyone", PlotFormat::png);
    ASSERT_TRUE(png.ok()) << png.error().message;
    EXPECT_EQ(png->substr(1, 3), "PNG");
}

// Issue 58: the window's recording onto a full disk (its recordings folder a 64 KiB tmpfs, the database
// beside it on a disk with room). The session is still stored, marked as having no recording (it would
// not replay), and the half-written folder goes. Needs root to mount the tmpfs; skipped otherwise.
TEST(StoredSessions, AWindowSessionWhoseRecordingFillsTheDiskIsStoredWithoutItAndTheFolderGoes) {
    const auto dir = fresh_dir();
    const auto recordings = dir / "recordings";
    std::filesystem::create_directories(recordings);
    const std::string mount = "mount -t tmpfs -o size=64k tmpfs '" + recordings.string() + "' 2>/dev/null";
    if (geteuid() != 0 || std::system(mount.c_str()) != 0) GTEST_SKIP() << "mounting a small tmpfs needs root";
    struct Unmount {
        std::filesystem::path at;
        ~Unmount() { (void)std::system(("umount '" + at.string() + "' 2>/dev/null").c_str()); }
    } unmount{recordings};
    WindowBench bench;
    window_bench(dir, bench);
    ASSERT_TRUE(bench.world);
    auto& options = bench.options;
    auto* lesson = &bench.lesson;
    auto* world = &bench.world;
    // Both hands moved by scripted devices, above the flowers: every sample that changes is a line.
    (*world)->attach_device(0, test::script({{0.0, -0.1, -0.1, 0.2, 0}, {3.0, -0.05, -0.1, 0.25, 0}}));
    (*world)->attach_device(1, test::script({{0.0, 0.1, -0.1, 0.2, 0}, {3.0, 0.05, -0.1, 0.25, 0}}));
    game::StoredSessions stored(options);
    (void)stored.open(false, &*lesson);
    stored.begin(**world, &*lesson);
    sched::DeterministicClock clock((*world)->schedule);
    clock.run_for_us(3'000'000); // two hands' samples at 1 kHz: far more than 64 KiB
    components::HudInfo hud;
    const auto* frames = (*world)->main.resource<const systems::ReceivedFrames>();
    ASSERT_TRUE(frames && frames->current) << "a frame was published";
    testing::internal::CaptureStderr();
    stored.store(session("sogetsu_basic_upright", "mika", 77.0, 1).result, frames->latest(), hud);
    EXPECT_FALSE(stored.finish(**world, &*lesson)) << "the app ends with status 1";
    stored.store_pending_at_exit();
    const std::string said = testing::internal::GetCapturedStderr();
    EXPECT_NE(said.find("the session is kept without its recording (it would not replay)"), std::string::npos) << said;
    auto db = ProgressDb::open_read_only(dir / "progress.sqlite");
    ASSERT_TRUE(db) << db.error().message;
    auto all = db->sessions();
    ASSERT_TRUE(all);
    ASSERT_EQ(all->size(), 1u) << "the session is stored";
    EXPECT_DOUBLE_EQ(all->front().result.score, 77.0);
    EXPECT_TRUE(all->front().recording.empty()) << "marked as having no recording: " << all->front().recording;
    EXPECT_TRUE(std::filesystem::is_empty(recordings)) << "the half-written folder goes";
}
