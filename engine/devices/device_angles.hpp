#pragma once
// A device's turn as devices report it (DeviceSample::rotation): angles about x, then y, then z, the
// turn being Rz(z) Ry(y) Rx(x). One convention for the grab system, the mouse's hands and the scripted
// teachers that drive them.
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace ikebana::devices {

[[nodiscard]] inline glm::dquat turn_of_angles(glm::dvec3 angles_rad) {
    return glm::angleAxis(angles_rad.z, glm::dvec3{0, 0, 1}) * glm::angleAxis(angles_rad.y, glm::dvec3{0, 1, 0}) *
           glm::angleAxis(angles_rad.x, glm::dvec3{1, 0, 0});
}

[[nodiscard]] inline glm::dvec3 angles_of_turn(const glm::dquat& turn) {
    const glm::dmat3 m = glm::mat3_cast(glm::normalize(turn)); // m[column][row]
    const double sy = std::clamp(-m[0][2], -1.0, 1.0);
    const double y = std::asin(sy);
    if (std::abs(sy) < 1.0 - 1e-12) return {std::atan2(m[1][2], m[2][2]), y, std::atan2(m[0][1], m[0][0])};
    // Straight sideways: only x - z (or x + z) is known; all of it is given to z.
    return {0.0, y, std::atan2(-m[1][0], m[1][1])};
}

} // namespace ikebana::devices
