#pragma once
// A species as designers write it (assets/species/<id>.json, documented in docs/species-format.md).
// Units are in the field names of the file; here everything is converted to SI once, on load.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include <glm/glm.hpp>
#include <vector>

#include "components/flower.hpp"
#include "components/insertion.hpp"
#include "engine/core/result.hpp"
#include "game/meshes/procedural_meshes.hpp"

namespace ikebana::game {

enum class CollisionClass : std::uint8_t { active, passive, inactive };
enum class BranchKind : std::uint8_t { soft, hard };

struct PartDef {
    components::PartKind kind;
    std::string mesh;           // beside the species file, or in assets/ (named_from); empty: procedural
    std::uint32_t count;        // arranged around the stem
    double position_along_stem; // 0 bottom .. 1 top
    double size_m;              // petal length or leaf length
    CollisionClass collision;
    // How the parts sit (species_format.md): each rises this far above the plane across the stem
    // (a cupped petal high, a flat ray low, a drooping leaf below); in this many rings, each inner one
    // shorter, more upright and turned half a step; their colours varied by up to this fraction.
    double tilt_rad = 0.0;
    double cup_rad = 0.0; // curled from base to tip toward the part's inside (negative: its tip droops)
    std::uint32_t whorls = 1;
    double colour_variation = 0.0;
    // Without a mesh: the shape drawn (its outline, width, tip and fold; docs/species-format.md).
    PartShape shape{};
};

// Side branches along a stem (or a twig), as designers give them (docs/species-format.md, "branches"):
// `count` twigs from `at` up the parent, `every` apart, each turned `turn` further about it than the one
// below (the golden angle by default, as many trees set their buds), leaving it at `angle`; each a stem
// of its own length, diameter, segments and mass (the parent's material), with its parts and twigs.
struct BranchDef {
    std::uint32_t count = 1;
    double position_along_parent = 0.5; // 0 bottom .. 1 top of the parent
    double spacing = 0.1;               // along the parent, between one twig and the next
    double angle_rad = 0.0;             // from the parent's line at the fork
    double azimuth_rad = 0.0;           // the first twig's side about the parent (0: along its bark's d1)
    double turn_rad = 0.0;              // each next twig's side, this much further round
    double shrink = 0.0;                // each next twig this fraction shorter (and lighter)
    double length_m = 0.0;
    double diameter_m = 0.0;
    std::uint32_t segments = 2;
    double mass_kg = 0.0;
    double rest_bend_rad = 0.0;         // its natural curve: up toward the light, or (negative) down, weeping
    std::vector<PartDef> parts;
    std::vector<BranchDef> branches;
};

// Section 2.5 and Table 1: resistance per mm of pin in contact with each tissue, tip (cone) and trunk
// (cylinder), and where the pith is.
struct HardResistance {
    double cortex_tip_n_per_m;
    double cortex_trunk_n_per_m;
    double pith_tip_n_per_m;
    double pith_trunk_n_per_m;
    double pith_diameter_m;
};

// Section 3.1 and Table 2, as measured: per insertion count, the resistance per mm and the maximum
// force on one pin. Index 0 is the first insertion.
struct SoftResistance {
    std::vector<double> n_per_m_by_insertion;
    std::vector<double> max_per_pin_n_by_insertion;
};

// How resistance changes with use. "paper_baseline": the paper's own model, Table 2's values for
// insertions 1 and 2 and the mean of 3-6 from the third on. "table_hold_last": the table as given,
// its last value from then on. "none": no change (hard branches in the paper).
struct DeteriorationDef {
    std::string model;
    std::string base_model;                        // "extended": the model the terms multiply
    std::vector<components::DeteriorationTerm> terms; // "extended": exp(sum of terms) factor
    // "extended": "push_and_hold" (the factor multiplies the holding moment too) or "push" (only the
    // resistance to the push; a stem at rest is held as the base model holds it).
    std::string applies_to = "push_and_hold";
    // Terms with "applies_to": "hold": they multiply only what holds a stem at rest in the pins (its
    // holding moment, so when it falls), never the resistance to the push (what a gauge reads). Found
    // from outcomes (stood, fell), where the forces cannot see them.
    std::vector<components::DeteriorationTerm> hold_terms;
};

// The stem bottom splitting (section 3.1: on average after 2.6 insertions).
struct BreakageDef {
    std::string model;                          // "hazard_by_insertion" or "none"
    std::vector<double> probability_by_insertion; // chance that insertion k breaks a sound bottom; last repeats
    double broken_holding_factor;               // a split end holds this fraction of a sound one
    double broken_seat_loss_m;                  // and seats this much less deep
};

struct SpeciesDef {
    std::string id;
    std::string name;
    std::filesystem::path file;
    BranchKind branch;
    // stem
    double length_m;
    double diameter_m;
    std::uint32_t segments;
    double stem_mass_kg;
    double youngs_modulus_pa;
    double poisson_ratio = 0.3;      // for twisting (G = E / 2(1 + nu)) when no shear modulus is given
    double shear_modulus_pa = 0.0;   // G; 0: from E and nu
    double second_moment_m4; // 0: solid circle
    double rest_bend_rad;
    double stiffness_damping_s;
    double air_drag_per_s;
    double permanent_set_rad; // bending beyond this leaves the stem bent (haptics issue)
    // head (flower head or none)
    double head_mass_kg;
    std::string head_mesh;
    std::vector<PartDef> parts;
    std::vector<BranchDef> branches; // side branches, recursively (none: a single stem)
    std::optional<HardResistance> hard;
    std::optional<SoftResistance> soft;
    DeteriorationDef deterioration;
    BreakageDef breakage;
    // "look": colours the renderer draws with (linear RGB 0..1); defaults by branch kind.
    glm::vec3 stem_colour;
    glm::vec3 petal_colour;
    glm::vec3 leaf_colour;
    glm::vec3 head_colour;

    [[nodiscard]] double total_mass_kg() const noexcept { return stem_mass_kg + head_mass_kg; }
};

// Parses and validates; on failure the error lists every problem found (one per line), and nothing
// of the file is used. `label` names the file in messages.
Result<SpeciesDef> parse_species(std::string_view text, const std::string& label);
// A species id: lower-case letters, digits, '-' and '_', not empty. A species file is named as its id.
[[nodiscard]] bool valid_species_id(std::string_view id) noexcept;
Result<SpeciesDef> load_species_file(const std::filesystem::path& path);
// An id ("sunflower") is looked up in <assets>/species/; anything with a slash or .json is a path.
Result<SpeciesDef> load_species(const std::string& id_or_path);

inline constexpr double gram_force_n = 9.80665e-3; // 1 gf in newtons

} // namespace ikebana::game
