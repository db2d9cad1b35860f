#pragma once
// The geometry the form scoring shares: a stem's tip and line, where a line is at a height, how far a
// point is outside a region of the kenzan and where on it it is in words, and whether two segments
// cross. Internal to game/training/.
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "game/lesson/lesson.hpp"
#include "game/training/arrangement.hpp"

namespace ikebana::game::training {

inline constexpr double pi = 3.14159265358979323846;
inline constexpr double deg = pi / 180.0;

// An angle in degrees in [-180, 180).
double wrap_deg(double a);

glm::dvec3 tip_of(const ArrangementStem& s);

// The stem as a polyline from its base, kenzan coordinates.
std::vector<glm::dvec3> polyline(const ArrangementStem& s);

// Where a polyline is at height z (its first crossing), if it reaches it.
std::optional<glm::dvec2> at_height(const std::vector<glm::dvec3>& p, double z);

// How far a point on the kenzan's face is outside a region of it, metres (0: inside).
double outside_region(glm::dvec2 b, KenzanRegion r, glm::dvec2 size);

std::string where_on_kenzan(glm::dvec2 b, glm::dvec2 size);

// Whether segment a0-a1 crosses segment b0-b1, and where.
bool segments_cross(glm::dvec2 a0, glm::dvec2 a1, glm::dvec2 b0, glm::dvec2 b1, glm::dvec2& at);

} // namespace ikebana::game::training
