#pragma once
// A window's frame times as they were presented: the whole frame (present to present), and where the
// time went (recording, the device's shadow, eyes and composite passes, presenting), as one line of
// p50 / p95 for the session's figures.
#include <chrono>
#include <string>
#include <vector>

#include "engine/render/stereo_renderer.hpp"

namespace ikebana::game {

class FrameTimings {
public:
    // A frame presented now, with its parts' timing.
    void add(const render::FrameTiming& timing);
    // "frame time, ms (p50 / p95): ..." and a newline; empty before three frames (the first includes
    // start-up and is left out).
    [[nodiscard]] std::string line() const;

private:
    std::chrono::steady_clock::time_point previous_ = std::chrono::steady_clock::now();
    std::vector<double> frame_ms_, record_ms_, shadow_ms_, eyes_ms_, composite_ms_, present_ms_;
};

} // namespace ikebana::game
