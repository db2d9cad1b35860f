#pragma once
// The offscreen renderer and the camera rig a scene describes: what `ikebana render`, the window and
// the replay share (below the app and the command line, so that both may use it).
#include <cstdint>
#include <string>

#include "engine/render/stereo_camera.hpp"
#include "game/scene/scene.hpp"

namespace ikebana::game {

struct RenderOptions {
    std::string scene;
    std::string lesson; // a lesson id or file instead of a scene: its table as a trainee first sees it
    std::uint32_t frames = 1;
    std::string stereo; // empty: the scene's "display"
    std::string out;
    std::uint32_t width = 1280;  // per eye
    std::uint32_t height = 720;
    double yaw_deg = 0.0;        // orbit the camera about the arrangement
    double pitch_deg = 0.0;
    std::uint32_t msaa = 4;      // samples a pixel (anti-aliasing); 1: none
    bool full_detail = false;    // every mesh as modelled, however small on screen
    // The validation layer: on by request, and always in debug builds.
#ifdef NDEBUG
    bool validation = false;
#else
    bool validation = true;
#endif
    bool quiet = false;
};

// The scene on the deterministic clock, each frame at the render rate drawn offscreen (no window, no
// display) into DIR as frame_NNNN_left.png, _right.png and _composed.png: `ikebana render`, and the
// app when there is no display.
int run_render(const RenderOptions& options);

// The camera rig a scene's display describes (the window's and `render`'s).
render::StereoRig rig_of(const DisplayDef& display);

} // namespace ikebana::game
