#include <gtest/gtest.h>

#include "systems/collision/narrow_phase.hpp"

using namespace ikebana;
using namespace ikebana::components;
using namespace ikebana::systems::collision;

namespace {
Collider sphere(glm::dvec3 c, double r) { return {ShapeKind::sphere, c, c, r, glm::dvec3{0.0}}; }
Collider capsule(glm::dvec3 a, glm::dvec3 b, double r) { return {ShapeKind::capsule, a, b, r, glm::dvec3{0.0}}; }
Collider box(glm::dvec3 c, double half) { return {ShapeKind::box, c, c, 0.0, glm::dvec3{half}}; }
} // namespace

TEST(NarrowPhase, SpheresReportDepthAndNormalFromBToA) {
    const auto hit = collide(sphere({0.015, 0, 0}, 0.01), sphere({0, 0, 0}, 0.01));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->depth_m, 0.005, 1e-12);
    EXPECT_NEAR(hit->normal.x, 1.0, 1e-12);
    EXPECT_FALSE(collide(sphere({0.021, 0, 0}, 0.01), sphere({0, 0, 0}, 0.01)));
}

TEST(NarrowPhase, CrossedCapsulesTouchAtTheirClosestPoints) {
    // One along x at z = 0, one along y at z = 0.008; radii 0.005 each: 2 mm overlap.
    const auto hit = collide(capsule({-0.05, 0, 0.008}, {0.05, 0, 0.008}, 0.005), capsule({0, -0.05, 0}, {0, 0.05, 0}, 0.005));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->depth_m, 0.002, 1e-12);
    EXPECT_NEAR(hit->normal.z, 1.0, 1e-12);
}

TEST(NarrowPhase, CapsuleEndCapAgainstSphere) {
    const auto hit = collide(capsule({0, 0, 0}, {0, 0, 0.1}, 0.004), sphere({0, 0, 0.11}, 0.008));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->depth_m, 0.002, 1e-12);
    EXPECT_NEAR(hit->normal.z, -1.0, 1e-12);
}

TEST(NarrowPhase, SphereInsideBoxIsPushedOutThroughNearestFace) {
    const auto hit = collide(sphere({0.008, 0, 0}, 0.002), box({0, 0, 0}, 0.01));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->normal.x, 1.0, 1e-12);
    EXPECT_NEAR(hit->depth_m, 0.004, 1e-12);
}

TEST(NarrowPhase, BoxAgainstCapsuleUsesTheSegmentsClosestPoint) {
    // A hand cube (edge 20 mm) touching a horizontal stem from above.
    const auto hit = collide(box({0.03, 0, 0.012}, 0.01), capsule({-0.1, 0, 0}, {0.1, 0, 0}, 0.004));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->depth_m, 0.002, 1e-6);
    EXPECT_NEAR(hit->normal.z, 1.0, 1e-6) << "from the stem towards the cube";
}

TEST(NarrowPhase, BoxesOverlapAlongTheirSmallestAxis) {
    const auto hit = collide(box({0.019, 0.005, 0}, 0.01), box({0, 0, 0}, 0.01));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->depth_m, 0.001, 1e-12);
    EXPECT_NEAR(hit->normal.x, 1.0, 1e-12);
}

TEST(NarrowPhase, PinTipIsAConeTrunkIsACylinder) {
    const PinShape pin{0.001, 0.011, 0.0015};
    const glm::dvec3 base{0, 0, 0};
    // A vertical stem coming down onto the pin, centred on it, bottom 0.5 mm below the point.
    const double r = 0.00375;
    const auto on_tip = collide_capsule_pin(capsule({0, 0, 0.012}, {0, 0, 0.1}, r), base, pin);
    ASSERT_TRUE(on_tip);
    // Beside the pin, 4 mm away: nothing, though within the trunk's height.
    EXPECT_FALSE(collide_capsule_pin(capsule({0.0045, 0, 0.005}, {0.0045, 0, 0.1}, 0.0), base, pin));
    // Grazing the trunk's side: penetration equals the overlap of radii.
    const auto side = collide_capsule_pin(capsule({0.0006, 0, 0.002}, {0.0006, 0, 0.1}, 0.0002), base, pin);
    ASSERT_TRUE(side);
    EXPECT_NEAR(side->depth_m, 0.0005 + 0.0002 - 0.0006, 1e-12);
    EXPECT_NEAR(side->normal.x, 1.0, 1e-9);
}

TEST(NarrowPhase, SegmentClosestPointsOfParallelSegments) {
    double s = -1.0;
    double t = -1.0;
    closest_segment_points({0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {2, 1, 0}, s, t);
    const glm::dvec3 p = glm::dvec3{0, 0, 0} + s * glm::dvec3{1, 0, 0};
    const glm::dvec3 q = glm::dvec3{0.5, 1, 0} + t * glm::dvec3{1.5, 0, 0};
    EXPECT_NEAR(glm::length(p - q), 1.0, 1e-12);
}
