#include "engine/render/stereo_camera.hpp"

#include <algorithm>
#include <cmath>

namespace ikebana::render {

glm::mat4 off_axis_projection(double l, double r, double b, double t, double n, double f) {
    glm::dmat4 p(0.0);
    p[0][0] = 2.0 * n / (r - l);
    p[1][1] = -2.0 * n / (t - b); // Vulkan's clip y points down
    p[2][0] = (r + l) / (r - l);
    p[2][1] = -(t + b) / (t - b);
    p[2][2] = f / (n - f);
    p[2][3] = -1.0;
    p[3][2] = n * f / (n - f);
    return glm::mat4(p);
}

namespace {
glm::dmat4 look_along(const glm::dvec3& eye, const glm::dvec3& forward, const glm::dvec3& up) {
    const glm::dvec3 f = glm::normalize(forward);
    const glm::dvec3 s = glm::normalize(glm::cross(f, up));
    const glm::dvec3 u = glm::cross(s, f);
    glm::dmat4 m(1.0);
    m[0][0] = s.x;
    m[1][0] = s.y;
    m[2][0] = s.z;
    m[0][1] = u.x;
    m[1][1] = u.y;
    m[2][1] = u.z;
    m[0][2] = -f.x;
    m[1][2] = -f.y;
    m[2][2] = -f.z;
    m[3][0] = -glm::dot(s, eye);
    m[3][1] = -glm::dot(u, eye);
    m[3][2] = glm::dot(f, eye);
    return m;
}
} // namespace

EyeMatrices eye_matrices(const StereoRig& rig, int eye) {
    const glm::dvec3 forward = glm::normalize(rig.target_m - rig.position_m);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, rig.up));
    const double offset = 0.5 * rig.eye_separation_m * static_cast<double>(std::clamp(eye, -1, 1));
    const glm::dvec3 position = rig.position_m + offset * right;
    // The screen rectangle is shared by both eyes; each eye sees it off-centre by its own offset.
    const double half_h = rig.screen_distance_m * std::tan(0.5 * rig.vertical_fov_rad);
    const double half_w = half_h * rig.aspect;
    const double scale = rig.near_m / rig.screen_distance_m;
    EyeMatrices m;
    m.view = glm::mat4(look_along(position, forward, rig.up));
    m.projection = off_axis_projection((-half_w - offset) * scale, (half_w - offset) * scale, -half_h * scale, half_h * scale, rig.near_m, rig.far_m);
    m.view_projection = m.projection * m.view;
    m.eye_position_m = position;
    return m;
}

namespace {
// The screen rectangle both eyes look through: its centre, its right and up unit vectors, half sizes.
struct Screen {
    glm::dvec3 centre, right, up, forward;
    double half_w, half_h;
};
Screen screen_of(const StereoRig& rig) {
    Screen s;
    s.forward = glm::normalize(rig.target_m - rig.position_m);
    s.right = glm::normalize(glm::cross(s.forward, rig.up));
    s.up = glm::cross(s.right, s.forward);
    s.centre = rig.position_m + s.forward * rig.screen_distance_m;
    s.half_h = rig.screen_distance_m * std::tan(0.5 * rig.vertical_fov_rad);
    s.half_w = s.half_h * rig.aspect;
    return s;
}
glm::dvec3 eye_position(const StereoRig& rig, const Screen& s, int eye) {
    return rig.position_m + 0.5 * rig.eye_separation_m * static_cast<double>(std::clamp(eye, -1, 1)) * s.right;
}
} // namespace

ViewRay eye_ray(const StereoRig& rig, int eye, glm::dvec2 uv) {
    const Screen s = screen_of(rig);
    const glm::dvec3 from = eye_position(rig, s, eye);
    const glm::dvec3 on_screen = s.centre + s.right * ((2.0 * uv.x - 1.0) * s.half_w) + s.up * ((1.0 - 2.0 * uv.y) * s.half_h);
    return {from, glm::normalize(on_screen - from)};
}

std::optional<glm::dvec2> eye_uv(const StereoRig& rig, int eye, const glm::dvec3& point_m) {
    const Screen s = screen_of(rig);
    const glm::dvec3 from = eye_position(rig, s, eye);
    const double ahead = glm::dot(point_m - from, s.forward);
    if (ahead <= 1e-9) return std::nullopt;
    const glm::dvec3 on_screen = from + (point_m - from) * (rig.screen_distance_m / ahead) - s.centre;
    return glm::dvec2{0.5 * (glm::dot(on_screen, s.right) / s.half_w + 1.0), 0.5 * (1.0 - glm::dot(on_screen, s.up) / s.half_h)};
}

StereoRig orbited(const StereoRig& rig, double yaw_rad, double pitch_rad) {
    StereoRig out = rig;
    const glm::dvec3 up = glm::normalize(rig.up);
    glm::dvec3 arm = rig.position_m - rig.target_m;
    const double distance = glm::length(arm);
    // Yaw about up.
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    arm = arm * c + glm::cross(up, arm) * s + up * glm::dot(up, arm) * (1.0 - c);
    // Pitch about the horizontal axis, kept short of the pole.
    const double elevation = std::asin(std::clamp(glm::dot(glm::normalize(arm), up), -1.0, 1.0));
    const double target_elevation = std::clamp(elevation + pitch_rad, -1.4, 1.4);
    const glm::dvec3 horizontal = glm::normalize(arm - up * glm::dot(arm, up));
    arm = distance * (horizontal * std::cos(target_elevation) + up * std::sin(target_elevation));
    out.position_m = rig.target_m + arm;
    return out;
}

} // namespace ikebana::render
