#pragma once
// Scenes (assets/scenes/*.json): what is on the table when a session starts, and the rates to run at.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/result.hpp"
#include "game/scene/container.hpp"
#include "systems/insertion/deterioration.hpp"

namespace ikebana::game {

enum class Placement : std::uint8_t {
    inserted, // standing in the kenzan, bottom held by the pins
    lying,    // lying on the table, ready to be picked up
};

struct FlowerPlacement {
    std::string species;
    Placement placement;
    glm::dvec3 base_m;      // bottom of the stem
    glm::dvec3 direction;   // unit, bottom to top
    double inserted_depth_m; // for Placement::inserted
    double length_m = 0.0;   // the stem as cut (a lesson's uncut material); 0: the species' own length
};

struct HandPlacement {
    std::uint8_t hand; // 0 left, 1 right
    glm::dvec3 position_m;
    double edge_m;
    std::string trajectory; // a scripted device for this hand (CSV, relative to assets/), or empty
};

// One stem of the sample arrangement the trainee copies (the paper's Figure 2): where it enters the
// kenzan, how it leans, how high its top stands.
struct SampleStem {
    std::string species;
    glm::dvec2 base_m;     // from the kenzan's centre
    double angle_rad;      // lean from the vertical
    double azimuth_rad;    // which way it leans, from +x towards +y
    double height_m;       // its top above the kenzan's base plate
};

// How the scene is shown (the display the trainee sits at): the stereo output and the rig. The command
// line's --stereo overrides the mode.
struct DisplayDef {
    std::string stereo = "sbs";      // sbs, rows (polarized, as in the paper), anaglyph, mono
    double eye_separation_m = 0.065;
    double screen_distance_m = 0.46; // the zero-parallax plane
    double vertical_fov_rad = 0.7;
    // Where the camera is and looks (a lesson's tall form needs it further back); the rig's defaults
    // when unset.
    std::optional<glm::dvec3> camera_position_m;
    std::optional<glm::dvec3> camera_target_m;
};

// Where a scene's things may be: within this distance of the origin on each axis (a table and the
// reach of two arms, with room to spare). Beyond it no arrangement is meant, and coordinates of 1e15 m
// once hung the collision grid.
inline constexpr double workspace_half_extent_m = 2.0;
// Gravity up to ten times the Earth's on each axis (a centrifuge, not a typo of 1e300).
inline constexpr double max_gravity_m_s2 = 100.0;
// More flowers than any arrangement uses (its placements are checked pairwise).
inline constexpr std::size_t max_scene_flowers = 1000;

struct SceneDef {
    std::filesystem::path file;
    std::uint64_t seed;
    std::map<std::string, double> rates_hz; // overrides of the rate table
    glm::dvec3 gravity_m_s2;
    double table_height_m;
    std::string kenzan_layout;
    glm::dvec3 kenzan_position_m;
    std::vector<FlowerPlacement> flowers;
    std::vector<HandPlacement> hands;
    // Values that are not part of the simulated world (a room temperature, a batch name) but that an
    // extended species model may depend on: the scene's "environment", overridden by --env.
    systems::insertion::Covariates environment;
    // "full_rate": hand forces every 1 kHz tick; "paper": the paper's 16 Hz check, 100 Hz estimate,
    // each force sent ten times.
    std::string force_scheme = "full_rate";
    std::vector<SampleStem> sample; // the arrangement to copy (empty: free practice)
    // The container the kenzan stands in (none: the kenzan stands on the table), centred here on the table.
    std::optional<ContainerDef> container;
    glm::dvec2 container_centre_m{0.0};
    DisplayDef display;
};

Result<SceneDef> parse_scene(std::string_view text, const std::string& label);
Result<SceneDef> load_scene(const std::filesystem::path& path);

// `--env name=value` settings over the scene's "environment": a value that parses as a number is
// numeric, anything else a category. All or nothing: on an error (naming the setting) the
// environment is unchanged.
Result<void> apply_environment_overrides(systems::insertion::Covariates& environment, const std::vector<std::string>& settings);
// A scene as loaded (a file's, or a lesson's) with those settings over its environment: the load's
// error, or the first bad setting's.
Result<SceneDef> with_environment(Result<SceneDef> scene, const std::vector<std::string>& settings);

} // namespace ikebana::game
