#include "game/session/seekable_playback.hpp"

#include <algorithm>

#include "game/world/world.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::game {

Result<std::unique_ptr<SeekablePlayback>> SeekablePlayback::open(const std::filesystem::path& folder, std::size_t max_moments) {
    auto s = std::unique_ptr<SeekablePlayback>(new SeekablePlayback());
    s->max_moments_ = std::max<std::size_t>(2, max_moments);
    auto shown = SessionPlayback::open(folder);
    if (!shown) return std::move(shown).error();
    auto reader = SessionPlayback::open(folder);
    if (!reader) return std::move(reader).error();
    s->shown_ = std::move(shown).value();
    s->reader_ = std::move(reader).value();
    s->marks_ = recorded_marks(*s->reader_);
    s->keep_moment(*s->shown_); // the start: going back there is a jump too
    return s;
}

void SeekablePlayback::go_to(std::int64_t t_us) { target_us_ = std::clamp<std::int64_t>(t_us, 0, end_us()); }

double SeekablePlayback::read_fraction() const {
    if (!reader_) return 1.0;
    return static_cast<double>(reader_->now_us()) / static_cast<double>(std::max<std::int64_t>(1, end_us()));
}

// No two moments closer than the spacing: the reader and the playback on screen both offer theirs.
void SeekablePlayback::keep_moment(const SessionPlayback& p) {
    const std::int64_t at = p.now_us();
    const auto next = std::lower_bound(moments_.begin(), moments_.end(), at, [](const Moment& m, std::int64_t t) { return m.at_us < t; });
    if (next != moments_.end() && next->at_us - at < spacing_us_) return;
    if (next != moments_.begin() && at - std::prev(next)->at_us < spacing_us_) return;
    auto snapshot = p.snapshot();
    if (!snapshot) return; // a cut waits for this tick: the next piece's end will do
    moments_.insert(next, Moment{at, std::move(snapshot).value()});
    if (moments_.size() <= max_moments_) return;
    // Too many: every other one goes (the start stays), and they are kept twice as far apart.
    std::vector<Moment> kept;
    for (std::size_t i = 0; i < moments_.size(); i += 2) kept.push_back(std::move(moments_[i]));
    moments_ = std::move(kept);
    spacing_us_ *= 2;
}

// The recording's score, on the frame it was scored on, the first time a playback passes that moment.
void SeekablePlayback::take_score(SessionPlayback& p) {
    if (replayed_score_ || p.now_us() != p.info().scored_us) return;
    auto frame = p.scored_frame();
    if (!frame) return;
    if (auto s = p.score(**frame); s) replayed_score_ = std::move(s).value();
}

// Either playback, on to `to` (stopping short at the scored moment, to score there), keeping a moment
// at the end if one is due; the simulated time it ran.
std::int64_t SeekablePlayback::play_piece(SessionPlayback& p, std::int64_t to) {
    const std::int64_t from = p.now_us(), scored = p.info().scored_us;
    if (from < scored && scored < to) to = scored;
    p.run_until(to);
    take_score(p);
    keep_moment(p);
    return to - from;
}

void SeekablePlayback::step(std::int64_t budget_us) {
    std::int64_t left = budget_us;
    const std::int64_t now = shown_->now_us();
    if (now != target_us_) {
        // The last moment at or before the target, if it is nearer than where the playback stands
        // (always, going back: the start is a moment).
        const auto after = std::upper_bound(moments_.begin(), moments_.end(), target_us_, [](std::int64_t t, const Moment& m) { return t < m.at_us; });
        if (after != moments_.begin()) {
            const Moment& m = *std::prev(after);
            if (target_us_ < now || m.at_us > now) (void)shown_->restore(*m.snapshot);
        }
    }
    while (left > 0 && shown_->now_us() < target_us_) {
        const std::int64_t from = shown_->now_us();
        // To the next moment's place, to keep one there on the way.
        const std::int64_t ran = play_piece(*shown_, std::min({target_us_, from + left, (from / spacing_us_ + 1) * spacing_us_}));
        shown_simulated_us_ += ran;
        left -= ran;
    }
    if (left > 0) read_ahead(left);
}

void SeekablePlayback::read_ahead(std::int64_t budget_us) {
    if (!reader_) return;
    const std::int64_t end = end_us();
    const std::int64_t until = std::min(end, reader_->now_us() + budget_us);
    std::vector<TimelineMark> seen;
    while (reader_->now_us() < until) {
        play_piece(*reader_, std::min(until, reader_->now_us() + read_piece_us));
        insertions_.watch(reader_->world().main.resource<const systems::ReceivedFrames>()->latest(), seen);
    }
    for (auto& m : seen) {
        const auto at = std::upper_bound(marks_.begin(), marks_.end(), m.at_us, [](std::int64_t t, const TimelineMark& k) { return t < k.at_us; });
        marks_.insert(at, std::move(m));
    }
    if (reader_->now_us() >= end) reader_.reset();
}

} // namespace ikebana::game
