#include <gtest/gtest.h>

#include <cmath>

#include "engine/render/stereo_camera.hpp"
#include "engine/render/text_overlay.hpp"

using namespace ikebana::render;

namespace {
glm::dvec2 ndc(const EyeMatrices& m, glm::dvec3 p) {
    const glm::dvec4 c = glm::dmat4(m.view_projection) * glm::dvec4(p, 1.0);
    return {c.x / c.w, c.y / c.w};
}
} // namespace

TEST(StereoCamera, EyesHaveAsymmetricFrustaNotToeIn) {
    const StereoRig rig;
    const auto left = eye_matrices(rig, -1), right = eye_matrices(rig, +1);
    // Off-axis: the projection's x-shear terms are equal and opposite; the view axes are parallel.
    EXPECT_GT(std::abs(left.projection[2][0]), 1e-4);
    EXPECT_NEAR(left.projection[2][0], -right.projection[2][0], 1e-6);
    EXPECT_NEAR(glm::length(glm::vec3(left.view[0][2], left.view[1][2], left.view[2][2]) -
                            glm::vec3(right.view[0][2], right.view[1][2], right.view[2][2])), 0.0, 1e-6);
    EXPECT_NEAR(glm::distance(left.eye_position_m, right.eye_position_m), rig.eye_separation_m, 1e-12);
}

TEST(StereoCamera, PointsOnTheScreenPlaneHaveNoParallaxAndNearOnesCross) {
    const StereoRig rig;
    const glm::dvec3 forward = glm::normalize(rig.target_m - rig.position_m);
    const auto left = eye_matrices(rig, -1), right = eye_matrices(rig, +1);
    const glm::dvec3 on_screen = rig.position_m + forward * rig.screen_distance_m;
    EXPECT_NEAR(ndc(left, on_screen).x, ndc(right, on_screen).x, 1e-5);
    const glm::dvec3 near_point = rig.position_m + forward * (0.5 * rig.screen_distance_m);
    const glm::dvec3 far_point = rig.position_m + forward * (2.0 * rig.screen_distance_m);
    const double near_parallax = ndc(left, near_point).x - ndc(right, near_point).x;
    const double far_parallax = ndc(left, far_point).x - ndc(right, far_point).x;
    EXPECT_GT(near_parallax, 0.0) << "a near point is further right in the left eye (crossed)";
    EXPECT_LT(far_parallax, 0.0);
    EXPECT_GT(std::abs(near_parallax), std::abs(far_parallax)) << "near objects shift more than far ones";
    // No vertical parallax anywhere (the point of not toeing in).
    const glm::dvec3 corner = near_point + glm::dvec3(0.1, 0.0, 0.08);
    EXPECT_NEAR(ndc(left, corner).y, ndc(right, corner).y, 1e-6);
}

TEST(StereoCamera, DepthIsZeroToOneAndYPointsDown) {
    const StereoRig rig;
    const auto m = eye_matrices(rig, 0);
    const glm::dvec3 forward = glm::normalize(rig.target_m - rig.position_m);
    auto depth = [&](double d) {
        const glm::dvec4 c = glm::dmat4(m.view_projection) * glm::dvec4(rig.position_m + forward * d, 1.0);
        return c.z / c.w;
    };
    EXPECT_NEAR(depth(rig.near_m), 0.0, 1e-5);
    EXPECT_NEAR(depth(rig.far_m), 1.0, 1e-5);
    const glm::dvec3 above = rig.target_m + rig.up * 0.05;
    EXPECT_LT(ndc(m, above).y, ndc(m, rig.target_m).y) << "Vulkan clip y points down";
}

TEST(StereoCamera, OrbitKeepsDistanceAndTarget) {
    const StereoRig rig;
    const StereoRig turned = orbited(rig, 1.0, 0.2);
    EXPECT_NEAR(glm::distance(turned.position_m, turned.target_m), glm::distance(rig.position_m, rig.target_m), 1e-9);
    EXPECT_GT(glm::distance(turned.position_m, rig.position_m), 0.1);
    const StereoRig over = orbited(rig, 0.0, 10.0);
    EXPECT_LT(glm::dot(glm::normalize(over.position_m - over.target_m), over.up), 0.99) << "pitch stops short of the pole";
}

TEST(StereoCamera, ALabelSitsOverWhatItNamesInEachEyeAtThatThingsDepth) {
    StereoRig rig;
    rig.aspect = 640.0 / 360.0;
    const glm::vec2 eye{640.0f, 360.0f};
    const auto left = eye_matrices(rig, -1), right = eye_matrices(rig, +1);
    OverlayPanel label;
    label.lines = {"Shin"};
    label.scale = 2.0f;
    const glm::vec2 size = overlay_extent_px(label);
    EXPECT_GT(size.x, 2.0f * 4 * 5) << "four letters, scaled";
    // Nearer than the screen plane: the left eye sees it further right than the right eye (crossed).
    const glm::vec3 near_point = glm::vec3(rig.target_m + 0.3 * (rig.position_m - rig.target_m));
    label.anchor_m = near_point;
    const auto in_left = overlay_origin_px(label, left.view_projection, eye);
    const auto in_right = overlay_origin_px(label, right.view_projection, eye);
    ASSERT_TRUE(in_left && in_right);
    EXPECT_GT(in_left->x - in_right->x, 5.0f) << "crossed parallax, as the thing itself";
    EXPECT_NEAR(in_left->y, in_right->y, 0.5f) << "no vertical parallax";
    // Centred above the point: the panel's middle on the point's column, its bottom edge over it.
    const glm::dvec2 seen = (ndc(left, glm::dvec3(near_point)) * 0.5 + 0.5) * glm::dvec2(eye);
    EXPECT_NEAR(in_left->x - 4.0f * label.scale + 0.5f * size.x, seen.x, 0.5);
    EXPECT_NEAR(in_left->y - 4.0f * label.scale + size.y, seen.y, 0.5);
    // On the screen plane: the same place in both eyes.
    label.anchor_m = glm::vec3(rig.target_m);
    EXPECT_NEAR(overlay_origin_px(label, left.view_projection, eye)->x, overlay_origin_px(label, right.view_projection, eye)->x, 0.5f);
    // Off the image's left edge: moved in until it is seen whole.
    label.anchor_m = glm::vec3(rig.target_m + glm::dvec3{-5.0, 0.0, 0.0});
    EXPECT_NEAR(overlay_origin_px(label, left.view_projection, eye)->x, 4.0f * label.scale, 1e-3f);
    // Behind the viewer: not drawn.
    label.anchor_m = glm::vec3(rig.position_m + (rig.position_m - rig.target_m));
    EXPECT_FALSE(overlay_origin_px(label, left.view_projection, eye).has_value());
    // A panel without an anchor stays where it was put.
    label.anchor_m.reset();
    label.origin_px = {12.0f, 30.0f};
    EXPECT_EQ(*overlay_origin_px(label, left.view_projection, eye), glm::vec2(12.0f, 30.0f));
}

TEST(StereoCamera, ThePointersRayThroughAnEyesImagePassesThroughWhatThatEyeShowsThere) {
    StereoRig rig;
    rig.aspect = 600.0 / 675.0;
    for (int eye : {-1, 0, 1}) {
        const auto m = eye_matrices(rig, eye);
        for (const glm::dvec3 p : {rig.target_m, glm::dvec3{0.12, 0.05, 0.02}, glm::dvec3{-0.2, -0.1, 0.3}}) {
            // Where the eye's projection draws the point, as uv of its image.
            const glm::dvec2 drawn = ndc(m, p) * 0.5 + 0.5;
            const auto uv = eye_uv(rig, eye, p);
            ASSERT_TRUE(uv);
            EXPECT_NEAR(uv->x, drawn.x, 1e-5) << eye;
            EXPECT_NEAR(uv->y, drawn.y, 1e-5) << eye;
            // The ray through that uv passes through the point.
            const ViewRay ray = eye_ray(rig, eye, *uv);
            EXPECT_NEAR(glm::length(ray.direction), 1.0, 1e-12);
            const glm::dvec3 to = p - ray.origin_m;
            EXPECT_NEAR(glm::length(glm::cross(to, ray.direction)), 0.0, 1e-9) << "the point lies on the ray";
            EXPECT_GT(glm::dot(to, ray.direction), 0.0) << "in front of the eye";
        }
    }
    EXPECT_FALSE(eye_uv(rig, 0, rig.position_m - (rig.target_m - rig.position_m)).has_value()) << "behind the eye";
}
