#include "game/render/frame_timings.hpp"

#include <cstdio>

#include "engine/core/percentile.hpp"

namespace ikebana::game {

void FrameTimings::add(const render::FrameTiming& timing, std::chrono::steady_clock::time_point input_read_at) {
    const auto end = std::chrono::steady_clock::now();
    frame_ms_.push_back(std::chrono::duration<double, std::milli>(end - previous_).count());
    own_ms_.push_back(std::chrono::duration<double, std::milli>(end - input_read_at).count());
    previous_ = end;
    record_ms_.push_back(timing.record_ms);
    shadow_ms_.push_back(timing.shadow_ms);
    eyes_ms_.push_back(timing.scene_ms);
    composite_ms_.push_back(timing.composite_ms);
    present_ms_.push_back(timing.present_ms);
    eye_triangles_.push_back(static_cast<double>(timing.eye_triangles));
    shadow_triangles_.push_back(static_cast<double>(timing.shadow_triangles));
}

std::string FrameTimings::line() const {
    if (frame_ms_.size() <= 2) return {};
    auto whole = frame_ms_;
    whole.erase(whole.begin()); // the first frame includes start-up
    auto own = own_ms_;
    own.erase(own.begin());
    char text[600];
    std::snprintf(text, sizeof text, "frame time, ms (p50 / p95): whole frame %.1f / %.1f; input read to presented %.1f / %.1f; record %.2f / %.2f; device: shadow %.1f / %.1f, both eyes %.1f / %.1f, "
                "composite and HUD %.1f / %.1f; present %.2f / %.2f\n"
                "triangles a frame (p50 / max): an eye's pass %.0f / %.0f, the shadow's %.0f / %.0f\n",
                percentile(whole, 0.5), percentile(whole, 0.95), percentile(own, 0.5), percentile(own, 0.95), percentile(record_ms_, 0.5), percentile(record_ms_, 0.95),
                percentile(shadow_ms_, 0.5), percentile(shadow_ms_, 0.95), percentile(eyes_ms_, 0.5), percentile(eyes_ms_, 0.95),
                percentile(composite_ms_, 0.5), percentile(composite_ms_, 0.95), percentile(present_ms_, 0.5), percentile(present_ms_, 0.95),
                  percentile(eye_triangles_, 0.5), percentile(eye_triangles_, 1.0), percentile(shadow_triangles_, 0.5), percentile(shadow_triangles_, 1.0));
    return text;
}

} // namespace ikebana::game
