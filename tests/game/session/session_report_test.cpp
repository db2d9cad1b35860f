// `ikebana report`'s page (issue 41): what a teacher hands back after a session.
#include <gtest/gtest.h>

#include <filesystem>

#include "engine/assets/files.hpp"
#include "game/lesson/lesson.hpp"
#include "game/progress/progress_db.hpp"
#include "game/session/lesson_demo.hpp"
#include "game/session/session_report.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {

std::uint32_t be32(const std::string& b, std::size_t at) {
    return (static_cast<std::uint32_t>(static_cast<unsigned char>(b[at])) << 24) | (static_cast<std::uint32_t>(static_cast<unsigned char>(b[at + 1])) << 16) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(b[at + 2])) << 8) | static_cast<std::uint32_t>(static_cast<unsigned char>(b[at + 3]));
}

} // namespace

// A recorded demonstration stored with an earlier session of the same trainee: the report finds it by
// its recording folder, with both sessions in its trend, and draws one page as PNG and PDF.
TEST(SessionReport, AStoredSessionsReportHasItsResultItsTrendAndIsWrittenAsPngAndPdf) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana_session_report";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    auto lesson = load_lesson("ohara_rising_form");
    ASSERT_TRUE(lesson.ok());
    DemoOptions options;
    options.record_dir = (dir / "recording").string();
    const auto demo = run_lesson_demo(*lesson, options);
    ASSERT_TRUE(demo.ok()) << demo.error().message;

    auto db = ProgressDb::open(dir / "progress.sqlite");
    ASSERT_TRUE(db.ok()) << db.error().message;
    SessionRecord earlier;
    earlier.lesson = "ohara_rising_form";
    earlier.trainee = "Aiko";
    earlier.started_unix_s = 1'790'000'000;
    earlier.result = demo->score;
    earlier.result.score = 61.0;
    ASSERT_TRUE(db->save(earlier).ok());
    SessionRecord now = earlier;
    now.id = 0;
    now.started_unix_s = 1'790'086'400;
    now.result = demo->score;
    now.recording = options.record_dir;
    ASSERT_TRUE(db->save(now).ok());
    SessionRecord someone_else = now;
    someone_else.id = 0;
    someone_else.trainee = "Ben";
    someone_else.recording.clear();
    ASSERT_TRUE(db->save(someone_else).ok());

    const auto report = load_session_report(options.record_dir, dir / "progress.sqlite");
    ASSERT_TRUE(report.ok()) << report.error().message;
    EXPECT_TRUE(report->in_database);
    EXPECT_EQ(report->session.trainee, "Aiko");
    EXPECT_DOUBLE_EQ(report->session.result.score, demo->score.score);
    ASSERT_EQ(report->trend.size(), 2u) << "Aiko's two sessions of the lesson, not Ben's";
    EXPECT_DOUBLE_EQ(report->trend[0].result.score, 61.0);
    EXPECT_FALSE(report->model.stems.empty());

    const auto png = render_session_report(*report, ReportFormat::png);
    ASSERT_TRUE(png.ok()) << png.error().message;
    ASSERT_GT(png->size(), 24u);
    EXPECT_EQ(png->substr(1, 3), "PNG");
    EXPECT_EQ(be32(*png, 16), 1123u) << "A4 landscape at 96 dpi";
    EXPECT_EQ(be32(*png, 20), 794u);
    const auto pdf = render_session_report(*report, ReportFormat::pdf);
    ASSERT_TRUE(pdf.ok()) << pdf.error().message;
    EXPECT_EQ(pdf->substr(0, 5), "%PDF-");

    ASSERT_TRUE(write_session_report(*report, dir / "out").ok());
    EXPECT_GT(std::filesystem::file_size(dir / "out" / "report.png"), 10'000u);
    EXPECT_GT(std::filesystem::file_size(dir / "out" / "report.pdf"), 5'000u);

    // Not in the database: replayed from its recording, the same result, no trend.
    const auto replayed = load_session_report(options.record_dir, dir / "no_such.sqlite");
    ASSERT_TRUE(replayed.ok()) << replayed.error().message;
    EXPECT_FALSE(replayed->in_database);
    EXPECT_TRUE(replayed->trend.empty());
    EXPECT_NEAR(replayed->session.result.score, demo->score.score, 1e-9);

    // A folder that is not a recording is named.
    const auto none = load_session_report(dir / "out", dir / "progress.sqlite");
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().message, (dir / "out").string() + ": not a session's recording (no session.json in it)");
    std::filesystem::remove_all(dir);
}
