#pragma once
// Grabbing and both-hand unification (Figure 5): pressing the button with a stem inside the hand cube
// unifies the cube with the nearest stem mass point; that point then follows the hand. Two hands may
// hold two flowers, or two points of one flower: the part held by neither then stretches or shrinks
// through its springs. Releasing the button, or losing the device, lets the point go (it falls, or
// stays if inserted in the kenzan). The grasp rules (who holds which point, when a one-hand grip keeps
// the stem's direction) live here and nowhere else.
#include <string_view>

#include <glm/gtc/quaternion.hpp>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"

namespace ikebana::systems {

struct GrabSystem {
    static constexpr std::string_view name = "grab";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::HandCube, components::HandInput, components::HandProxy, components::StemRestShape,
                                    components::WorkspaceMapping, components::InsertionHistory, components::StemFork>;
    using writes = sched::Components<components::HandGrip, components::StemPoints, components::StemFrame, components::Grasp>;

    void operator()(sched::SystemContext& ctx);

    // How fast a held stem turns after the device (a wrist turns a stem about this fast): a mouse
    // drag that jumps is followed over several ticks, not in one.
    double max_turn_rad_s = 6.0;
};

// The turn of a device reporting (roll, pitch, yaw) = rotation_rad: about x (right), then y (away
// from the viewer), then z (up), in the device's frame; `yaw_rad` turns that frame with the camera.
glm::dquat device_turn(glm::dvec3 rotation_rad, double yaw_rad);

// Lets go of whatever the grip holds (on release and on disconnect).
void release_hold(ecs::Registry& registry, components::HandGrip& grip);

// Lets go of the second point of a one-hand grip (a second hand took the flower, or the hand lets go);
// the held point stays held.
void let_go_of_direction(ecs::Registry& registry, components::HandGrip& grip);

} // namespace ikebana::systems
