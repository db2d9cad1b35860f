#pragma once
// What the main thread gets from the simulation each frame: a copy, never a reference into the
// simulation's registry (the two live on different threads in real time).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/draw_list.hpp"

namespace ikebana::components {

struct StemPose {
    std::uint32_t flower;               // index in the scene's flower list
    std::vector<glm::dvec3> points_m;
};

struct HandStatus {
    bool present;       // the scene has this hand
    bool connected;     // its device answers
    std::uint64_t disconnects;
};

struct FrameSnapshot {
    std::int64_t sim_time_us;
    std::vector<StemPose> stems;
    std::uint64_t contacts;
    HandStatus hands[2];
    render::DrawList draw_list; // what the renderer draws this frame
};

} // namespace ikebana::components
