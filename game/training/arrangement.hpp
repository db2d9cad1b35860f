#pragma once
// An arrangement as the scoring reads it: each stem's species, where it enters the kenzan, its length,
// tilt and direction, whether it stands, and optionally its shape.
//
// An arrangement is data (`ikebana lesson score --arrangement FILE`): what a demo or the app measured,
// or what a teacher measured on a real arrangement and typed in. The same JSON is what the result's
// "arrangement" holds, so a result can be edited and scored again.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/result.hpp"

namespace ikebana::game {

struct ArrangementStem {
    std::string role;    // empty: let the scoring choose; "supporting": a supporting stem (jushi)
    std::string species;
    glm::dvec2 base_m{0.0};   // where it enters the kenzan, from the kenzan's centre (x right, y away from the viewer)
    double length_m = 0.0;    // from where it enters the kenzan to its tip
    double tilt_rad = 0.0;    // of the line from base to tip, from the vertical
    double azimuth_rad = 0.0; // which way it leans, seen from above: 0 toward the viewer, + to the viewer's left
    bool standing = true;     // false: it fell (or lies on the table)
    // Optional: the stem's shape, points from its base up, kenzan coordinates (x, y as base_m; z above
    // the kenzan's plate). A straight line from base to tip when empty.
    std::vector<glm::dvec3> path_m;
    // Optional: how high above the kenzan's plate each of its leaves (its twigs' too) meets the bark, as
    // path_m's z. Leaves under the water rot (the rule no_leaves_under_water).
    std::vector<double> leaf_heights_m;
};

struct Arrangement {
    std::optional<glm::dvec2> kenzan_offset_m; // where the kenzan sits in the container (the lesson's when unset)
    std::vector<ArrangementStem> stems;
};

inline constexpr std::size_t max_arrangement_stems = 200;
inline constexpr std::size_t max_path_points = 200;
inline constexpr std::size_t max_leaf_heights = 2000;

// An arrangement's JSON: {"stems": [...]} or a whole result whose "arrangement" is one.
Result<Arrangement> parse_arrangement(std::string_view text, const std::string& label);
Result<Arrangement> load_arrangement(const std::filesystem::path& path);
[[nodiscard]] std::string arrangement_json(const Arrangement& arrangement, int indent = 1);

} // namespace ikebana::game
