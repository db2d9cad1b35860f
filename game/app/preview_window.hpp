#pragma once
// `ikebana species preview FILE --window`: the designer's preview on screen instead of in PNGs. The
// flower turns on its turntable (drag to turn it by hand); keys 1-5 show the trials (upright, set at
// 0, 45 and 70 degrees, held level by its base) with their numbers over the picture; with --watch a
// save measures and shows it again, and a file that no longer loads is said over the last good one.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "components/snapshot.hpp"
#include "engine/core/result.hpp"
#include "engine/render/stereo_camera.hpp"

namespace ikebana::game {

// One thing to look at: a trial's last frame and what it showed.
struct PreviewView {
    std::string key;                  // what shows it ("1")
    std::string title;                // in the list of views ("turntable")
    components::FrameSnapshot frame;
    std::vector<std::string> caption;
    bool turning = false;             // turns by itself (the turntable)
};

struct PreviewWindowOptions {
    std::string file;
    std::uint32_t width = 480, height = 640;
    bool watch = false;
    std::uint32_t passes = 0;   // with watch: after this many measurements, a few frames more and stop (0: never)
    std::uint32_t frames = 0;   // stop after this many presented frames (0: until Esc or the window closes)
    std::string screenshot;     // the last frame, as PNG
    bool validation = false;
};

// A camera framing the flowers of a frame whole (their stems, with room for a head and petals), seen
// from the front and a little above, turned `yaw_rad` about the vertical through them.
render::StereoRig preview_framing(const components::FrameSnapshot& frame, double aspect, double yaw_rad);

// Measures (runs the trials) at start and, with watch, after each save. The exit code: 0; 2 when the
// file cannot be measured at start; 3 without a display or Vulkan.
int run_preview_window(const PreviewWindowOptions& options, const std::function<Result<std::vector<PreviewView>>()>& measure);

} // namespace ikebana::game
