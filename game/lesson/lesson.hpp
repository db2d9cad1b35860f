#pragma once
// Lessons (assets/lessons/<id>.json, documented in docs/lesson-format.md): a school's form as data. The
// container and where the kenzan sits in it, the materials handed to the trainee, the form's main
// stems (their roles and the bands their length, tilt, direction and place on the kenzan must fall
// in) and the rules a teacher checks. Lengths and angles are converted to SI once, on load.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/result.hpp"
#include "game/scene/container.hpp"

namespace ikebana::game {

// What a length target is a ratio of.
struct LengthBase {
    enum class Kind : std::uint8_t { container_size, container_height, role } kind = Kind::container_size;
    std::size_t role = 0; // Kind::role: an earlier main stem, by index
};

struct Band {
    double target = 0.0;
    double tolerance = 0.0; // full points within target ± tolerance
};

// Where on the kenzan a stem enters, as a part of its face.
enum class KenzanRegion : std::uint8_t { any, centre, front, back, left, right, front_left, front_right, back_left, back_right };

struct MainStemDef {
    std::string role;                  // "shin", "soe", "hikae", "subject", ...
    std::string label;                 // how the result names it, "Shin (heaven)"
    std::vector<std::string> species;  // which materials may play it (empty: any)
    LengthBase length_of;
    Band length_ratio;                 // length above the kenzan / the base's length
    std::vector<double> length_also;   // other ratios the school also teaches (Sogetsu's hikae: 1/2 of soe besides 3/4), same tolerance
    Band tilt_rad;                     // from the vertical
    std::optional<Band> azimuth_rad;   // which way it leans, seen from above: 0 toward the viewer, + to the viewer's left
    KenzanRegion region = KenzanRegion::any;
};

struct MaterialDef {
    std::string species;
    std::uint32_t count = 1;
    double length_m = 0.0; // uncut; 0: the species' own length
};

// Supporting stems (jushi): what is not a main stem.
struct SupportingDef {
    std::uint32_t max_count = 0;
    std::string label = "Supporting stems"; // the school's name: Sogetsu's jushi, Ohara's fillers
    // Each must be shorter than this main stem (by index), when set.
    std::optional<std::size_t> shorter_than_role;
};

enum class RuleKind : std::uint8_t {
    odd_main_stems,      // an odd number of main stems stand
    no_crossing_front,   // no two stems cross in the front view
    kenzan_hidden_front, // from the front, low stems cover the kenzan
    kenzan_off_centre,   // the kenzan is not in the container's centre
    one_line_at_water,   // the stems rise together as one line above the water for a while
    supporting_count,    // no more supporting stems than the lesson allows, each shorter than its main stem
    no_leaves_under_water, // no standing stem has a leaf under the water line (they rot)
};

struct RuleDef {
    RuleKind kind;
    double min_m = 0.0; // one_line_at_water: the bundle holds at least this high ...
    double max_m = 0.0; // ... and parts by this height
    double points = 4.0;
    bool supporting_only = false; // kenzan_hidden_front: only the supporting stems (jushi, fillers) hide it, as Sogetsu and Ohara teach
};

struct LessonDef {
    std::filesystem::path file;
    std::string id;
    std::string title;
    std::string school;
    std::string source; // where its numbers come from
    std::string summary; // one or two sentences the trainee reads first
    // 1 (a first lesson) to 5: the start screen lists the forms by it, so a newcomer starts on a 1.
    int level = 3;
    // "form": scored against main stems and rules. "sample": free practice, scored against a scene's
    // sample as the paper's Figure 2 does.
    std::string scoring = "form";
    std::string scene; // "sample" lessons: the scene whose sample is copied (relative to assets/)
    ContainerDef container;
    std::string kenzan_layout = "standard";
    glm::dvec2 kenzan_offset_m{0.0}; // the kenzan's centre from the container's, x to the right, y away
    std::vector<MaterialDef> materials;
    std::vector<MainStemDef> stems;
    SupportingDef supporting;
    std::vector<RuleDef> rules;
    // Points for each criterion of a main stem. The tilt weighs most: it is what tells one form from
    // another (Sogetsu's upright and slanting styles differ only in it).
    double length_points = 8.0;
    double tilt_points = 14.0;
    double azimuth_points = 5.0;
    double region_points = 3.0;
};

inline constexpr std::size_t max_lesson_stems = 8;     // main stems in a form
inline constexpr std::size_t max_lesson_materials = 32;

// The text of a lesson file; every problem names the field by its JSON path.
Result<LessonDef> parse_lesson(std::string_view text, const std::string& label);
// A file, with what it names checked: its species, kenzan layout and scene exist; the kenzan fits the
// container; each main stem has a material long enough for its nominal length.
Result<LessonDef> load_lesson_file(const std::filesystem::path& path);
// An id ("sogetsu_basic_upright") is looked up in <assets>/lessons/; anything with a slash or .json is a path.
Result<LessonDef> load_lesson(const std::string& id_or_path);
// The shipped lessons (every file in <assets>/lessons/), by id; the first file that fails stops it.
// The order a start screen lists lessons in: the school forms by level (a newcomer's first choice is
// a first lesson), keeping their order within a level; free practice against a sample last.
void order_for_newcomers(std::vector<LessonDef>& lessons);
Result<std::vector<LessonDef>> load_shipped_lessons();

// A main stem's nominal length (its targets' product down the chain of roles), metres.
[[nodiscard]] double nominal_length_m(const LessonDef& lesson, std::size_t stem);
// The viewer's words for a direction ("left front") and a region ("the back left").
[[nodiscard]] std::string direction_words(double azimuth_rad);
[[nodiscard]] std::string region_words(KenzanRegion region);
[[nodiscard]] std::string rule_name(RuleKind kind);
// The unit vector of a stem tilted `tilt_rad` from the vertical toward `azimuth_rad` (lesson convention).
[[nodiscard]] glm::dvec3 lesson_direction(double tilt_rad, double azimuth_rad);
// How far from `from` (a point inside a container, from its centre) along the level unit direction `way`
// a wall is: a round one of radius half_extent.x, or a box's sides at +-half_extent.
[[nodiscard]] double distance_to_wall_m(bool round, glm::dvec2 half_extent, glm::dvec2 from, glm::dvec2 way);

} // namespace ikebana::game
