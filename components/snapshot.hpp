#pragma once
// What the main thread gets from the simulation each frame: a copy, never a reference into the
// simulation's registry (the two live on different threads in real time).
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/draw_list.hpp"

namespace ikebana::components {

// One flower as the trainee sees it: where its stem is and how it stands in the kenzan.
struct FlowerStatus {
    std::string species;
    std::vector<glm::dvec3> points_m;   // the stem's mass points, bottom first
    std::uint32_t insertions;           // over its life, across cuts
    bool bottom_broken;
    bool in_kenzan;
    bool fallen;
    double holding_moment_nm;           // what the pins can hold
    double gravity_moment_nm;           // what its weight asks of them
};

struct HandStatus {
    bool present;       // the scene has this hand
    bool connected;     // its device answers
    std::uint64_t disconnects;
    bool holding;       // it holds a stem
    glm::dvec3 force_n; // what it feels (before the device's safety chain)
};

struct FrameSnapshot {
    std::int64_t sim_time_us;
    std::vector<FlowerStatus> flowers;
    std::uint64_t contacts;
    HandStatus hands[2];
    render::DrawList draw_list; // what the renderer draws this frame
};

} // namespace ikebana::components
