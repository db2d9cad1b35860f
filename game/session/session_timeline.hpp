#pragma once
// What a teacher looks for in a recorded session, on its timeline: each cut (the commands file), each
// tilt of a held stem (a hand's device turning, from its samples) and each insertion into the kenzan
// (a flower's insertion count rising, seen in the frames the simulation publishes).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "components/snapshot.hpp"
#include "engine/core/result.hpp"
#include "game/session/lesson_session.hpp"

namespace ikebana::game {

struct TimelineMark {
    enum class Kind : std::uint8_t { cut, tilt, insertion };
    std::int64_t at_us = 0;
    Kind kind = Kind::cut;
    std::string what; // "cut: right hand's stem to 420 mm", "tilt: left hand", "insertion: cherry_branch (2nd)"
};

// The cuts and tilts, known from the recording's files.
[[nodiscard]] std::vector<TimelineMark> recorded_marks(const SessionPlayback& playback);

// Insertions, frame by frame.
class InsertionWatcher {
public:
    void watch(const components::FrameSnapshot& frame, std::vector<TimelineMark>& marks);

private:
    std::vector<std::uint32_t> seen_;
};

// The whole timeline: the recording played once through (a second playback; `progress` is told the
// simulated seconds done and in all), marks in time order.
Result<std::vector<TimelineMark>> session_timeline(const std::filesystem::path& folder, const std::function<void(double done_s, double of_s)>& progress = {});

} // namespace ikebana::game
