#pragma once
// The trainee's hands (paper 2.4): each device drives a hand cube. The device's position maps into
// the world through a workspace mapping that can follow the camera; the cube itself (the proxy) never
// goes through rigid things, and the spring between the two is part of what the hand feels.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/ecs/entity.hpp"

namespace ikebana::components {

// The hand of the paper: a cube driven by one haptic device.
struct HandCube {
    std::uint8_t hand;     // 0 left, 1 right
    double edge_m;
};

// Whether a press takes a stem point: inside the cube, grown by the stem's radius, on every axis. The
// grab and what the window marks as "this is what a press would take" use this one rule.
[[nodiscard]] inline bool within_grab(glm::dvec3 point_m, glm::dvec3 cube_centre_m, double edge_m, double stem_diameter_m) {
    const glm::dvec3 d = glm::abs(point_m - cube_centre_m);
    const double reach = 0.5 * edge_m + 0.5 * stem_diameter_m;
    return d.x <= reach && d.y <= reach && d.z <= reach;
}

struct WorkspaceMapping {
    glm::dvec3 centre_m;    // where the device's centre lands in the world
    double scale;           // world metres per device metre (position devices)
    double yaw_rad;         // turns with the camera, so "away from me" stays away from the viewer
    double rate_speed_m_s;  // rate devices (a SpaceMouse): hand speed at a full push
    // Rate devices: turn speed at a full twist. The twist is integrated like the push, so a stem turned
    // with a SpaceMouse stays turned when the cap is let go (a held angle would spring back to upright).
    double rate_turn_rad_s;
};

// A hand is four components, one per step of the chain, each written by one system:
// HandInput (hand_input: what the device said), HandProxy (hand_input: where the cube is), HandGrip
// (grab: what it holds) and HandForce (the force systems: what it should feel).

// What a hand's device link is doing, for the HUD and the session's figures.
enum class DeviceLink : std::uint8_t {
    answering,
    not_answering, // never answered yet (a device being opened)
    unplugged,     // its reads fail: gone from the bus
    silent,        // plugged in but sending nothing new (a hung firmware, a stalled hub)
    lost,          // it stopped taking forces (writes failed again and again): being reopened
};
[[nodiscard]] inline const char* device_link_words(DeviceLink link) {
    switch (link) {
    case DeviceLink::answering: return "answering";
    case DeviceLink::not_answering: return "not answering";
    case DeviceLink::unplugged: return "unplugged";
    case DeviceLink::silent: return "silent: no reports; hand released, force taken away";
    case DeviceLink::lost: return "not taking forces: released, reconnecting";
    }
    return "unknown";
}

struct HandInput {
    bool connected;
    glm::dvec3 device_m;        // where the device puts the hand
    glm::dvec3 rotation_rad;    // the device's rotation (roll, pitch, yaw); bending uses the roll
    std::uint32_t buttons;
    std::uint32_t previous_buttons;
    std::uint64_t disconnects;  // times the device went away
};

// The hand cube as drawn and as it touches things: the device position, kept out of rigid things.
struct HandProxy {
    glm::dvec3 position_m;
    glm::dvec3 slip_m_s;        // how fast the proxy moves relative to the device (coupling damping)
};

struct HandGrip {
    ecs::Entity held;           // the flower it holds, or null
    std::uint32_t held_point;   // which of its stem's mass points
    glm::dvec3 held_offset_m;   // where that point was relative to the cube when grabbed
    // A hand that holds a flower alone also holds its neighbouring point: a grip spans a length of stem,
    // so it keeps the stem's direction (a single held point would let a heavy head swing the stem
    // round like a pendulum). With two hands on one flower each holds one point, and the line between
    // the hands gives the direction.
    bool holds_direction;
    std::uint32_t second_point;
    glm::dvec3 second_offset_m;
    // A one-hand grip turns with the hand: the offsets above are as they were when the grip took the
    // stem's direction, turned by how far the device has turned since (`turn_at_grip`: its turn in the
    // room then, the camera's yaw of that moment included, so that a camera turned since turns nothing
    // by itself). `turned` is the turn applied so far, which follows the device's at a hand's pace.
    glm::dquat turn_at_grip{1.0, 0.0, 0.0, 0.0};
    glm::dquat turned{1.0, 0.0, 0.0, 0.0};
    std::uint32_t cuts_seen = 0; // the held stem's cuts when last gripped (a cut moves its points)
    // The bark under the fist: the held segment's director (StemFrame) when the grip took the stem's
    // direction. The grip holds it turned as the hand has turned since, so the stem turns about its
    // own axis with the wrist and a bend keeps its side while carried.
    glm::dvec3 director_at_grip{0.0};
};

struct HandForce {
    glm::dvec3 force_n;         // what the hand should feel (the device's safety layer comes after)
};

// Both-hand bending on one flower (paper Figures 6-8): set by bending_system while both hands bend it.
struct Bending {
    bool active;
    double theta_rad;           // angle between the two halves; pi is straight
    double span_m;              // L, between the supports A and B (the index fingers)
    std::uint32_t support_a;    // stem point indices
    std::uint32_t support_b;
    glm::dvec3 push_direction;  // where the thumbs push the middle (unit)
    double force_n;             // F^b (Eq. 5), felt by both hands
    double permanent_set_rad;   // the species' threshold (bending beyond it stays)
    double set_applied_rad;     // how much permanent set this flower has taken so far
    // The bend is counted from how the wrists were rolled when both hands came together on the stem
    // (two devices are never held at the same roll), and follows them at a wrist's speed: a stem
    // taken by a second hand rolled half a turn from the first is not bent half a turn in a tick.
    bool hands_together;        // both hands held it, tips together, at the last tick
    double roll_at_start_rad;   // roll_left - roll_right when they came together
    double bent_rad;            // pi - theta as the stem follows the wrists
};

// The paper's multi-rate force scheme (section 2.3), per hand: the force is checked at 16 Hz,
// estimated at 100 Hz from the last two checks (the moving vector) and the same estimate is sent ten
// times at 1 kHz.
struct ForceChecks {
    glm::dvec3 last_n;
    glm::dvec3 previous_n;
    std::int64_t last_us;
    std::int64_t previous_us;
    std::uint32_t checks;
};

// Every force sent to each hand's device, for measurements (a sim-lane resource, off by default).
struct SentForceLog {
    bool enabled;
    std::vector<glm::dvec3> hand[2];
};

} // namespace ikebana::components
