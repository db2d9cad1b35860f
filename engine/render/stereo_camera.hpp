#pragma once
// Stereo projection for the paper's polarized display (section 2.1): two eyes side by side, parallel
// view axes, and an off-axis (asymmetric) frustum per eye through the same physical screen rectangle
// at `screen_distance_m`. Points on that plane have zero parallax; nearer points cross. Toe-in (rotating
// each eye towards the target) would add vertical parallax at the image edges and is not used.
// Matrices are for Vulkan: right-handed view space, clip y pointing down, depth 0..1.
#include <optional>

#include <glm/glm.hpp>

namespace ikebana::render {

struct StereoRig {
    // Defaults frame a kenzan at the origin and flowers up to 30 cm tall, seen from where a trainee sits.
    glm::dvec3 position_m{0.0, -0.42, 0.3};
    glm::dvec3 target_m{0.0, 0.0, 0.11};
    glm::dvec3 up{0.0, 0.0, 1.0};
    double eye_separation_m = 0.065;
    double screen_distance_m = 0.46; // the zero-parallax plane, along the view axis (about the target)
    double vertical_fov_rad = 0.7;   // of the screen rectangle seen from the rig's centre
    double aspect = 16.0 / 9.0;      // width / height of one eye's image
    double near_m = 0.02;
    double far_m = 5.0;
};

struct EyeMatrices {
    glm::mat4 view;
    glm::mat4 projection;
    glm::mat4 view_projection;
    glm::dvec3 eye_position_m;
};

// eye: -1 left, +1 right, 0 the centre (mono).
EyeMatrices eye_matrices(const StereoRig& rig, int eye);

// An off-axis perspective projection for Vulkan from the near-plane rectangle.
glm::mat4 off_axis_projection(double left, double right, double bottom, double top, double near_m, double far_m);

// Where an eye's image shows things, for a pointer: uv in [0, 1] across the eye's image, (0, 0) at
// its top left. The ray from the eye through the point of its image at uv (unit direction), and the
// uv at which the eye sees a point (nothing for a point level with or behind the eye).
struct ViewRay {
    glm::dvec3 origin_m{0.0};
    glm::dvec3 direction{0.0, 1.0, 0.0};
};
ViewRay eye_ray(const StereoRig& rig, int eye, glm::dvec2 uv);
std::optional<glm::dvec2> eye_uv(const StereoRig& rig, int eye, const glm::dvec3& point_m);

// Orbits the rig about its target: yaw about `up`, pitch towards it, keeping the distance.
StereoRig orbited(const StereoRig& rig, double yaw_rad, double pitch_rad);

} // namespace ikebana::render
