#pragma once
// A window's frame times as they were presented: the whole frame (present to present), a frame's own
// time (from reading the input it shows to presenting it: what the frame's work takes, and how late
// the trainee sees their hand), and where the time went (recording, the device's shadow, eyes and
// composite passes, presenting), as lines of p50 / p95 for the session's figures. At a paced rate the
// whole frame is the pace whatever the work (30 Hz: 33.3 ms, its p95 above by the work's own jitter);
// the frame's own time says whether the work fits in it.
#include <chrono>
#include <string>
#include <vector>

#include "engine/render/stereo_renderer.hpp"

namespace ikebana::game {

class FrameTimings {
public:
    // A frame presented now, with its parts' timing, showing the input read at `input_read_at`.
    void add(const render::FrameTiming& timing, std::chrono::steady_clock::time_point input_read_at);
    // "frame time, ms (p50 / p95): ..." and "triangles a frame ...", each a line; empty before three
    // frames (the first includes start-up and is left out).
    [[nodiscard]] std::string line() const;

private:
    std::chrono::steady_clock::time_point previous_ = std::chrono::steady_clock::now();
    std::vector<double> frame_ms_, own_ms_, record_ms_, shadow_ms_, eyes_ms_, composite_ms_, present_ms_, eye_triangles_, shadow_triangles_;
};

} // namespace ikebana::game
