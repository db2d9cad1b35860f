// The replay window's snapshots (issue 41): a moment of a playback, put back into it or into another
// playback of the same recording, plays on to the very state the recording reaches played straight.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "game/lesson/lesson.hpp"
#include "game/session/lesson_demo.hpp"
#include "game/session/lesson_session.hpp"
#include "game/session/seekable_playback.hpp"
#include "game/session/session_timeline.hpp"
#include "game/world/world.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {
// The Ohara demonstration on record in DIR/recording (DIR emptied first); its result.
Result<DemoResult> record_demo(const std::filesystem::path& dir) {
    std::filesystem::remove_all(dir);
    auto lesson = load_lesson("ohara_rising_form");
    if (!lesson) return std::move(lesson).error();
    DemoOptions options;
    options.record_dir = (dir / "recording").string();
    return run_lesson_demo(*lesson, options);
}
} // namespace

TEST(PlaybackSnapshot, AMomentPutBackIntoAnyPlaybackOfTheRecordingPlaysOnToTheSameState) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana_playback_snapshot";
    const auto demo = record_demo(dir);
    ASSERT_TRUE(demo.ok()) << demo.error().message;

    auto straight = SessionPlayback::open(dir / "recording");
    ASSERT_TRUE(straight.ok()) << straight.error().message;
    SessionPlayback& a = **straight;
    const std::int64_t end = a.info().end_us;
    // A moment between the cuts and the insertions, and one near the end.
    const std::int64_t early = end / 3, late = 2 * end / 3;
    a.run_until(early);
    auto at_early = a.snapshot();
    ASSERT_TRUE(at_early.ok()) << at_early.error().message;
    a.run_until(late);
    const std::uint64_t hash_late = a.state_hash();
    auto at_late = a.snapshot();
    ASSERT_TRUE(at_late.ok()) << at_late.error().message;
    a.run_until(end);
    const std::uint64_t hash_end = a.state_hash();
    EXPECT_EQ(hash_end, demo->state_hash) << "played straight, the recording reaches its own end";

    // Back in the same playback: from the early moment, on to the late one and the end.
    ASSERT_TRUE(a.restore(**at_early).ok());
    EXPECT_EQ(a.now_us(), early);
    a.run_until(late);
    EXPECT_EQ(a.state_hash(), hash_late);
    a.run_until(end);
    EXPECT_EQ(a.state_hash(), hash_end);

    // In another playback that has just opened (a jump forward past what it has played) and in one
    // that had played further (a jump back).
    auto fresh = SessionPlayback::open(dir / "recording");
    ASSERT_TRUE(fresh.ok());
    ASSERT_TRUE((*fresh)->restore(**at_late).ok());
    EXPECT_EQ((*fresh)->state_hash(), hash_late);
    (*fresh)->run_until(end);
    EXPECT_EQ((*fresh)->state_hash(), hash_end);
    ASSERT_TRUE((*fresh)->restore(**at_early).ok());
    (*fresh)->run_until(end);
    EXPECT_EQ((*fresh)->state_hash(), hash_end);
    // What the window draws from is the moment's too: the frame the main lane holds.
    EXPECT_EQ((*fresh)->world().main.resource<const systems::ReceivedFrames>()->latest().sim_time_us,
              a.world().main.resource<const systems::ReceivedFrames>()->latest().sim_time_us);
    std::filesystem::remove_all(dir);
}

TEST(PlaybackSnapshot, AMomentOfAnotherRecordingIsRefusedAndNothingChanges) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana_playback_snapshot_other";
    std::filesystem::remove_all(dir);
    ASSERT_TRUE(record_demo(dir / "one").ok());
    ASSERT_TRUE(record_demo(dir / "two").ok());
    auto one = SessionPlayback::open(dir / "one" / "recording");
    auto two = SessionPlayback::open(dir / "two" / "recording");
    ASSERT_TRUE(one.ok() && two.ok());
    (*one)->run_until(2'000'000);
    auto moment = (*one)->snapshot();
    ASSERT_TRUE(moment.ok());
    (*two)->run_until(1'000'000);
    const auto before = (*two)->state_hash();
    const auto refused = (*two)->restore(**moment);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("a moment of another recording"), std::string::npos) << refused.error().message;
    EXPECT_EQ((*two)->now_us(), 1'000'000);
    EXPECT_EQ((*two)->state_hash(), before);
    std::filesystem::remove_all(dir);
}

namespace {
// Reads the whole recording ahead (the window does it while the trainee watches).
void read_all(SeekablePlayback& s) {
    for (int guard = 0; s.read_fraction() < 1.0 && guard < 100000; ++guard) s.step(1'500'000);
}
// Goes to `t_us` as the window does, a budget a frame; the simulated time the playback on screen ran.
std::int64_t jump(SeekablePlayback& s, std::int64_t t_us) {
    const std::int64_t before = s.shown_simulated_us();
    s.go_to(t_us);
    for (int guard = 0; !s.arrived() && guard < 100000; ++guard) s.step(1'500'000);
    return s.shown_simulated_us() - before;
}
} // namespace

// Issue 41: scrubbing from 123 s to 586 s took 2.5 minutes. Once the recording has been read ahead, a
// jump anywhere, back or forth, plays at most the moments' spacing and a reading piece (5.1 simulated
// seconds, under half a second here) and reaches the state a straight playback has there; the reader's marks are the
// timeline's and its score the recording's.
TEST(SeekablePlayback, OnceReadAJumpAnywherePlaysAtMostFiveSecondsToTheStateAStraightPlaybackReaches) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana_seekable_playback";
    const auto demo = record_demo(dir);
    ASSERT_TRUE(demo.ok()) << demo.error().message;

    auto opened = SeekablePlayback::open(dir / "recording");
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    SeekablePlayback& s = **opened;
    const std::int64_t end = s.end_us();
    read_all(s);
    EXPECT_EQ(s.shown_simulated_us(), 0) << "with no jump asked for, the budget went to reading ahead";
    EXPECT_GE(s.moments(), static_cast<std::size_t>(end / SeekablePlayback::moment_every_us));
    ASSERT_TRUE(s.replayed_score().has_value());
    EXPECT_EQ(s.replayed_score()->score, demo->score.score);
    const auto timeline = session_timeline(dir / "recording");
    ASSERT_TRUE(timeline.ok());
    ASSERT_EQ(s.marks().size(), timeline->size());
    for (std::size_t i = 0; i < timeline->size(); ++i) EXPECT_EQ(s.marks()[i].at_us, (*timeline)[i].at_us) << (*timeline)[i].what;

    // The states a straight playback reaches, in time order.
    // (The last goes back before the first moment after the start, which was kept before any system
    // had fired: what the systems made since, their scratch, goes with the restore.)
    const std::vector<std::int64_t> targets{end * 9 / 10, end / 5, end * 3 / 5, 0, end, end / 2 + 1234, 2'345'678};
    std::vector<std::int64_t> sorted = targets;
    std::sort(sorted.begin(), sorted.end());
    std::map<std::int64_t, std::uint64_t> straight;
    auto p = SessionPlayback::open(dir / "recording");
    ASSERT_TRUE(p.ok());
    for (const std::int64_t t : sorted) {
        (*p)->run_until(t);
        straight[t] = (*p)->state_hash();
    }
    for (const std::int64_t t : targets) {
        const std::int64_t cost = jump(s, t);
        EXPECT_EQ(s.now_us(), t);
        EXPECT_LE(cost, SeekablePlayback::moment_every_us + SeekablePlayback::read_piece_us) << "to " << t << " us";
        EXPECT_EQ(s.shown().state_hash(), straight[t]) << "at " << t << " us";
    }
    std::filesystem::remove_all(dir);
}

// A long session keeps at most so many moments: past that, every other one goes and they are kept
// twice as far apart; a jump then plays at most the wider spacing.
TEST(SeekablePlayback, PastItsMostMomentsItKeepsThemTwiceAsFarApart) {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana_seekable_playback_few";
    ASSERT_TRUE(record_demo(dir).ok());
    auto opened = SeekablePlayback::open(dir / "recording", 4);
    ASSERT_TRUE(opened.ok());
    SeekablePlayback& s = **opened;
    read_all(s);
    EXPECT_LE(s.moments(), 4u);
    EXPECT_GT(s.moment_spacing_us(), SeekablePlayback::moment_every_us);
    const std::int64_t end = s.end_us();
    EXPECT_LE(jump(s, end - 1), s.moment_spacing_us() + 2 * SeekablePlayback::read_piece_us);
    EXPECT_LE(jump(s, end / 3), s.moment_spacing_us() + 2 * SeekablePlayback::read_piece_us);
    EXPECT_EQ(s.now_us(), end / 3);
    std::filesystem::remove_all(dir);
}
