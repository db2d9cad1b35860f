#pragma once
// A recording played to be looked at (the replay window's): the playback on screen goes to any moment
// in a second or two, back or forth. A second playback reads ahead through the whole recording once,
// finding the insertions for the timeline and keeping a moment (SessionPlayback::snapshot) every few
// simulated seconds; the one on screen jumps to the nearest moment before where it is asked to be and
// plays the rest. Going back used to play the recording again from its start: 2.5 minutes from
// 586 s back to 123 s.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "engine/core/result.hpp"
#include "game/session/lesson_session.hpp"
#include "game/session/session_timeline.hpp"

namespace ikebana::game {

class SeekablePlayback {
public:
    // A moment every this many simulated seconds: at about 12 times real time, half a second of
    // playing at most to reach any point from the moment before it. At 0.7 MB a moment (Sogetsu's
    // scene), a 10-minute session keeps about 80 MB.
    static constexpr std::int64_t moment_every_us = 5'000'000;
    // The reader looks for insertions (and may keep a moment) after each piece this long (as
    // `session_timeline` does): moments lie between the spacing and the spacing and a piece apart, and
    // a jump plays at most that.
    static constexpr std::int64_t read_piece_us = 100'000;
    // Past `max_moments`, every other one is dropped (and moments are kept twice as far apart, give or
    // take the pieces they were kept at): a long session costs at most this many moments' memory.
    static constexpr std::size_t default_max_moments = 240;

    static Result<std::unique_ptr<SeekablePlayback>> open(const std::filesystem::path& folder, std::size_t max_moments = default_max_moments);

    // The playback on screen.
    [[nodiscard]] SessionPlayback& shown() { return *shown_; }
    [[nodiscard]] std::int64_t now_us() const { return shown_->now_us(); }
    [[nodiscard]] std::int64_t end_us() const { return shown_->info().end_us; }
    // Where the playback on screen is to go (clamped to the recording).
    void go_to(std::int64_t t_us);
    [[nodiscard]] std::int64_t target_us() const { return target_us_; }
    [[nodiscard]] bool arrived() const { return shown_->now_us() == target_us_; }
    // At most `budget_us` of simulated time: first toward the target (from the nearest moment before
    // it, if that is closer than where the playback stands), then, with what is left, reading ahead.
    void step(std::int64_t budget_us);

    // The cuts and tilts (known from the files) and the insertions read so far, in time order.
    [[nodiscard]] const std::vector<TimelineMark>& marks() const { return marks_; }
    // How far the reading ahead is (0..1); 1 once it has read the whole recording.
    [[nodiscard]] double read_fraction() const;
    // The score as this playback reached it (the reader passes the scored moment for sure).
    [[nodiscard]] const std::optional<FormScore>& replayed_score() const { return replayed_score_; }
    // The moments kept, and how much simulated time the playback on screen has run in all (what a
    // jump cost).
    [[nodiscard]] std::size_t moments() const { return moments_.size(); }
    [[nodiscard]] std::int64_t moment_spacing_us() const { return spacing_us_; }
    [[nodiscard]] std::int64_t shown_simulated_us() const { return shown_simulated_us_; }

private:
    SeekablePlayback() = default;
    void keep_moment(const SessionPlayback& playback);
    void read_ahead(std::int64_t budget_us);
    void take_score(SessionPlayback& playback);
    std::int64_t play_piece(SessionPlayback& playback, std::int64_t to_us);

    std::unique_ptr<SessionPlayback> shown_;
    std::unique_ptr<SessionPlayback> reader_; // null once it has read to the end
    struct Moment {
        std::int64_t at_us;
        std::shared_ptr<const PlaybackSnapshot> snapshot;
    };
    std::vector<Moment> moments_; // in time order
    std::int64_t spacing_us_ = moment_every_us;
    std::size_t max_moments_ = default_max_moments;
    std::vector<TimelineMark> marks_;
    InsertionWatcher insertions_;
    std::optional<FormScore> replayed_score_;
    std::int64_t target_us_ = 0;
    std::int64_t shown_simulated_us_ = 0;
};

} // namespace ikebana::game
