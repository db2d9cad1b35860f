#pragma once
// What the main thread gets from the simulation each frame: a copy of plain state, never a reference
// into the simulation's registry (the two live on different threads in real time), and nothing drawn:
// the main lane prepares the draw list and the HUD from it (extract here, prepare and draw there).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "components/appearance.hpp"
#include "components/flower.hpp"
#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "engine/devices/haptic_device.hpp"

namespace ikebana::components {

// A side branch of a flower, as drawn: its points (its first is the point of the stem or twig it leaves),
// its bark's turn, its thickness and its leaves and blossoms.
struct TwigStatus {
    std::vector<glm::dvec3> points_m;
    std::vector<glm::dvec3> directors;
    double diameter_m = 0.0;
    std::vector<Part> parts;
};

// One flower as the trainee sees it: where its stem is, how it looks and how it stands in the kenzan.
struct FlowerStatus {
    std::string species;
    std::vector<glm::dvec3> points_m;   // the stem's mass points, bottom first
    std::vector<glm::dvec3> directors;  // its bark's turn, one a segment (StemFrame), or none
    std::uint32_t insertions;           // over its life, across cuts
    bool bottom_broken;
    bool in_kenzan;
    bool fallen;                        // one definition: KenzanGrip's (see FallReason)
    FallReason fall_reason;
    double fall_yield_holding_nm;       // when the pins first gave way, if they did (0: never)
    double fall_yield_gravity_nm;
    double holding_moment_nm;           // what the pins can hold
    double gravity_moment_nm;           // what its weight asks of them
    std::uint32_t pins_engaged;         // pins touching its end
    double depth_m;                     // its end below the pin tips (in the kenzan)
    double diameter_m;                  // the stem's
    FlowerLook look;
    std::vector<Part> parts;            // petals and leaves (the stem is drawn from its points)
    std::vector<TwigStatus> twigs;      // its side branches, parents before their twigs (none: a single stem)
};

struct HandStatus {
    bool present;       // the scene has this hand
    bool connected;     // its device answers
    std::uint64_t disconnects;
    bool holding;       // it holds a stem
    glm::dvec3 force_n; // what the simulation asks it to feel (before the device's safety chain)
    glm::dvec3 position_m; // where its cube is
    double edge_m;
    std::int32_t held_flower = -1; // which of the frame's flowers it holds (-1: none)
    glm::dvec3 device_m{0.0};      // where its device puts it (the cube stops above the table; this does not)
    bool grab_button = false;      // its grab button is down (with nothing held: a press that took nothing)
    // What its device really got: the force after the safety chain (clamp, rate limit, wait, ramp),
    // why that differs from force_n, and the state of the link. `pushes`: false for a device that
    // pushes nothing (the mouse), whose hand feels nothing.
    devices::SentForce sent{};
    DeviceLink link = DeviceLink::answering;
    std::uint64_t write_failures = 0;
};

// What was pruned off and lies loose: a twig with its own twigs, leaves and blossoms, or a stripped leaf.
struct CuttingStatus {
    FlowerLook look;
    std::vector<TwigStatus> pieces; // the cutting itself first, then its twigs
};

struct FrameSnapshot {
    std::int64_t sim_time_us;
    std::vector<FlowerStatus> flowers;
    std::uint64_t contacts;
    HandStatus hands[2];
    std::optional<Kenzan> kenzan;
    std::optional<double> table_height_m;
    std::optional<Container> container;
    std::vector<CuttingStatus> cuttings;
};

} // namespace ikebana::components
