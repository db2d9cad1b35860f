#include "game/session/session_timeline.hpp"

#include <algorithm>
#include <cstdio>

#include "game/world/world.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::game {

namespace {
constexpr std::int64_t tilt_gap_us = 2'000'000; // turns closer together than this are one tilt (a Ctrl+drag comes in pieces)
const char* hand_name(std::size_t hand) { return hand ? "right hand" : "left hand"; }

std::string ordinal(std::uint32_t n) {
    const char* suffix = (n % 100 >= 11 && n % 100 <= 13) ? "th" : n % 10 == 1 ? "st" : n % 10 == 2 ? "nd" : n % 10 == 3 ? "rd" : "th";
    return std::to_string(n) + suffix;
}
} // namespace

std::vector<TimelineMark> recorded_marks(const SessionPlayback& playback) {
    std::vector<TimelineMark> marks;
    for (const auto& c : playback.commands()) {
        if (c.what != SessionCommand::What::cut) continue;
        char what[96];
        if (c.command.kind == systems::TraineeCommand::Kind::prune) std::snprintf(what, sizeof what, "prune: at the %s", hand_name(c.command.hand));
        else std::snprintf(what, sizeof what, "cut: the %s's stem to %.0f mm", hand_name(c.command.hand), c.command.keep_length_m * 1e3);
        marks.push_back({c.at_us, TimelineMark::Kind::cut, what});
    }
    for (std::size_t hand = 0; hand < 2; ++hand) {
        const auto& keys = playback.samples(hand);
        std::int64_t last_turn_us = -tilt_gap_us - 1;
        for (std::size_t i = 1; i < keys.size(); ++i) {
            if (keys[i].rotation_rad == keys[i - 1].rotation_rad) continue;
            const auto at = static_cast<std::int64_t>(std::llround(keys[i].time_s * 1e6));
            if (at - last_turn_us > tilt_gap_us) marks.push_back({at, TimelineMark::Kind::tilt, std::string("tilt: the ") + hand_name(hand) + "'s stem"});
            last_turn_us = at;
        }
    }
    std::stable_sort(marks.begin(), marks.end(), [](const TimelineMark& a, const TimelineMark& b) { return a.at_us < b.at_us; });
    return marks;
}

void InsertionWatcher::watch(const components::FrameSnapshot& frame, std::vector<TimelineMark>& marks) {
    if (seen_.size() < frame.flowers.size()) seen_.resize(frame.flowers.size(), 0);
    for (std::size_t i = 0; i < frame.flowers.size(); ++i) {
        const auto& f = frame.flowers[i];
        if (f.insertions > seen_[i]) marks.push_back({frame.sim_time_us, TimelineMark::Kind::insertion, "insertion: " + f.species + " (its " + ordinal(f.insertions) + ")"});
        seen_[i] = f.insertions;
    }
}

Result<std::vector<TimelineMark>> session_timeline(const std::filesystem::path& folder, const std::function<void(double, double)>& progress) {
    auto opened = SessionPlayback::open(folder);
    if (!opened) return std::move(opened).error();
    SessionPlayback& p = **opened;
    auto marks = recorded_marks(p);
    InsertionWatcher insertions;
    const std::int64_t end = p.info().end_us;
    constexpr std::int64_t step_us = 100'000;
    for (std::int64_t t = 0; t < end;) {
        t = std::min(end, t + step_us);
        p.run_until(t);
        insertions.watch(p.world().main.resource<const systems::ReceivedFrames>()->latest(), marks);
        if (progress) progress(static_cast<double>(t) * 1e-6, static_cast<double>(end) * 1e-6);
    }
    std::stable_sort(marks.begin(), marks.end(), [](const TimelineMark& a, const TimelineMark& b) { return a.at_us < b.at_us; });
    return marks;
}

} // namespace ikebana::game
