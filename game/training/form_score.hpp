#pragma once
// Scoring an arrangement against a lesson's form, criterion by criterion, the way a teacher corrects
// it: each stem gets its role (shin, soe, hikae; subject, object; ...), then each of its criteria
// (length, tilt, direction, place on the kenzan) gives the target, the band, what was measured, the
// points and one plain tip naming the stem; then the lesson's rules are checked likewise.
//
// The arrangement scored and its JSON: arrangement.hpp. The pieces, each in its own file: which stem
// plays which role (role_assignment), a stem's criteria (stem_scoring), the rules (form_rules), the
// form's model arrangement (model_arrangement.cpp), the geometry they share (stem_geometry).
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/result.hpp"
#include "game/lesson/lesson.hpp"
#include "game/scene/scene.hpp"
#include "game/training/arrangement.hpp"

namespace ikebana::game {

struct Criterion {
    std::string stem; // the role
    std::string name; // "length_mm", "tilt_deg", "azimuth_deg", "region_mm", "match"
    double target = 0.0;
    double tolerance = 0.0;
    std::optional<double> measured; // none: no stem plays the role
    double points = 0.0;
    double max_points = 0.0;
    std::string tip;
};

struct RuleResult {
    std::string name;
    bool ok = false;
    double points = 0.0;
    double max_points = 0.0;
    std::string tip;
};

struct FormScore {
    std::string lesson;
    double score = 0.0; // 0..100: points earned / points possible
    std::vector<Criterion> criteria;
    std::vector<RuleResult> rules;
    Arrangement arrangement; // with the roles the scoring gave
    std::string how;         // how points are given, in a sentence or two
    [[nodiscard]] std::string json(int indent = 1) const;
    // For a terminal or the result panel: the score, then each role's worst tip, then failed rules.
    [[nodiscard]] std::vector<std::string> lines() const;
};

// Where the kenzan is, for the rules that look at it.
// A one-line form's stem (one with a straight rise, `path_m` of two points) leaning more than this above
// its rise is bent before it goes in: the demonstration bends it, the HUD tells a trainee to.
inline constexpr double one_line_bend_beyond_rad = 18.0 * 3.14159265358979323846 / 180.0;
// How far a stem's line leans from upright above its straight rise (0 for a stem without one).
[[nodiscard]] double lean_above_rise_rad(const ArrangementStem& s);

struct KenzanFootprint {
    glm::dvec2 size_m{0.08, 0.08};
    double plate_thickness_m = 0.008;
};

// Scores a "form" lesson. Errors (an unknown role, a role given twice) name the arrangement's field.
Result<FormScore> score_form(const LessonDef& lesson, const Arrangement& arrangement, const KenzanFootprint& kenzan,
                             const std::string& label = "arrangement");

// Scores a free-practice lesson against its scene's sample with the paper's Figure 2 comparison
// (training/arrangement_score): one criterion per sample stem, "match", whose points are that stem's
// share of the score; its tip gives the direction, height and place errors.
FormScore score_sample(const LessonDef& lesson, const Arrangement& arrangement, const std::vector<SampleStem>& sample);

// The form's model arrangement: each main stem at its nominal length, tilt, direction and place; where
// the lesson wants the stems to rise as one line from the water, they do so before they part; and
// where it wants the kenzan hidden, low supporting stems lean toward the front until it is. What a
// teacher shows, what the demonstration aims at, and what every shipped form scores >= 90 against.
[[nodiscard]] Arrangement model_arrangement(const LessonDef& lesson, const KenzanFootprint& kenzan);

// The water's surface above the kenzan's plate, as the rules see it: a suiban's water over the
// kenzan; in a vase, the mouth where the stems are held (the kenzan stands in for a kubari there).
[[nodiscard]] double water_level_m(const LessonDef& lesson, const KenzanFootprint& kenzan);

// How much of a straight stem's length lies below the pins' tops when its bottom is `depth_m` under
// them and it leans `tilt_rad`: depth / cos(tilt). The scoring measures a stem from where its line
// crosses the pins' tops, so a stem cut "pin height longer than its target" and leaned 70 degrees
// came out 20-40 mm short (a first-time trainee's hikae: cut for 0.75 x soe, scored against 0.50).
// Beyond 80 degrees it counts as at 80 (a stem lying in the pins is not a length anyone cuts for).
[[nodiscard]] double in_pins_along_m(double depth_m, double tilt_rad);

// How far a point of the kenzan's face (from its centre) is outside a region of it, metres (0: in it),
// as the score judges a stem's place.
[[nodiscard]] double outside_place_m(glm::dvec2 at_m, KenzanRegion region, const KenzanFootprint& kenzan);

// Points for a measured error against a band: all of them within it; outside, outside_band_share of
// them at its edge, falling linearly to none one band further (a band of 0 counts as the kenzan's
// pitch, 4 units). A school's band is a rule, not a slope.
inline constexpr double outside_band_share = 0.3;
[[nodiscard]] double band_points(double error, double tolerance, double max_points);
// Points for a stem's base `outside_mm` from its part of the kenzan: all at 0, none at 8 mm.
[[nodiscard]] double position_points(double outside_mm, double max_points);

} // namespace ikebana::game
