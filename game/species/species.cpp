#include "game/species/species.hpp"

#include <cmath>
#include <system_error>

#include <glm/gtc/constants.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/asset_paths.hpp"

namespace ikebana::game {

namespace {
// A deterioration term's origin, scale and range: any finite value a column may hold.
constexpr double term_value_limit = 1.7e308;
} // namespace

using assets::Json;
using assets::JsonChecker;
using assets::NumberRange;

namespace {

constexpr double mm = 1e-3;
constexpr double deg = glm::pi<double>() / 180.0;
// gf/mm -> N/m
constexpr double gf_per_mm = gram_force_n / 1e-3;

std::optional<CollisionClass> collision_of(const std::optional<std::string>& s) {
    if (!s) return std::nullopt;
    if (*s == "active") return CollisionClass::active;
    if (*s == "passive") return CollisionClass::passive;
    return CollisionClass::inactive;
}

void read_stem(JsonChecker& c, const Json& root, SpeciesDef& out) {
    const Json* stem = c.object(root, "", "stem");
    if (!stem) return;
    const std::string p = "/stem";
    c.no_unknown_keys(*stem, p, {"length_mm", "diameter_mm", "segments", "mass_g", "youngs_modulus_mpa",
                                 "second_moment_mm4", "rest_bend_deg", "stiffness_damping_s", "air_drag_per_s",
                                 "permanent_set_deg", "poisson_ratio", "shear_modulus_mpa"});
    out.length_m = c.number(*stem, p, "length_mm", {10, 3000}).value_or(0) * mm;
    out.diameter_m = c.number(*stem, p, "diameter_mm", {0.5, 100}).value_or(0) * mm;
    out.segments = static_cast<std::uint32_t>(c.integer(*stem, p, "segments", 2, 200).value_or(0));
    out.stem_mass_kg = c.number(*stem, p, "mass_g", {0.01, 5000, true}).value_or(0) * 1e-3;
    out.youngs_modulus_pa = c.number(*stem, p, "youngs_modulus_mpa", {0.1, 50000}).value_or(0) * 1e6;
    out.second_moment_m4 = c.number(*stem, p, "second_moment_mm4", {0, 1e9, true}, false).value_or(0) * 1e-12;
    out.rest_bend_rad = c.number(*stem, p, "rest_bend_deg", {0, 180}, false).value_or(0) * deg;
    out.stiffness_damping_s = c.number(*stem, p, "stiffness_damping_s", {0, 1}, false).value_or(0.004);
    out.air_drag_per_s = c.number(*stem, p, "air_drag_per_s", {0, 100}, false).value_or(1.0);
    out.permanent_set_rad = c.number(*stem, p, "permanent_set_deg", {1, 180}, false).value_or(45) * deg;
    out.poisson_ratio = c.number(*stem, p, "poisson_ratio", {0, 0.5}, false).value_or(0.3);
    out.shear_modulus_pa = c.number(*stem, p, "shear_modulus_mpa", {0.01, 20000}, false).value_or(0) * 1e6;
}

void read_head(JsonChecker& c, const Json& root, SpeciesDef& out) {
    const Json* head = c.object(root, "", "head", false);
    if (!head) return;
    c.no_unknown_keys(*head, "/head", {"mass_g", "mesh"});
    out.head_mass_kg = c.number(*head, "/head", "mass_g", {0, 5000}).value_or(0) * 1e-3;
    out.head_mesh = c.string(*head, "/head", "mesh", false).value_or("");
}

// A part without a mesh is drawn as a shape: its outline (a petal's, a leaf's, an iris's sword), its
// width, its tip and its fold, each with a default from its kind. With a mesh they would mean nothing:
// refused rather than ignored.
void read_part_shape(JsonChecker& c, const Json& part, const std::string& p, PartDef& def) {
    const bool leaf = def.kind == components::PartKind::leaf;
    const auto outline = c.choice(part, p, "shape", {"petal", "leaf", "sword"}, false).value_or(leaf ? "leaf" : "petal");
    def.shape.outline = outline == "sword" ? PartOutline::sword : outline == "leaf" ? PartOutline::leaf : PartOutline::petal;
    const double default_width = def.shape.outline == PartOutline::sword ? 0.08 : def.shape.outline == PartOutline::leaf ? 0.44 : 0.32;
    const double size_mm = def.size_m / mm;
    const auto width_mm = c.number(part, p, "width_mm", {0.1, 1000, true}, false);
    if (width_mm && size_mm > 0.0 && *width_mm > size_mm) {
        c.problem(p + "/width_mm", "expected at most the part's size_mm (" + JsonChecker::describe(part["size_mm"]) + "): a part is measured along its length, got " + JsonChecker::describe(part["width_mm"]));
    }
    def.shape.width = width_mm && size_mm > 0.0 ? std::min(1.0, *width_mm / size_mm) : default_width;
    def.shape.round_tip = c.choice(part, p, "tip", {"pointed", "round"}, false).value_or("pointed") == "round";
    const double default_fold = def.shape.outline == PartOutline::sword ? 20.0 : def.shape.outline == PartOutline::leaf ? 14.0 : 0.0;
    def.shape.fold_rad = c.number(part, p, "fold_deg", {0, 80}, false).value_or(default_fold) * deg;
    if (!def.mesh.empty()) {
        for (const char* key : {"shape", "width_mm", "tip", "fold_deg"}) {
            if (part.contains(key)) c.problem(p + "/" + key, std::string("describes the shape drawn without a mesh, and this part names one (/mesh): give one or the other"));
        }
    }
}

// The parts of the object at JSON path `at` (the species, or one of its branches).
void read_parts(JsonChecker& c, const Json& owner, const std::string& at, std::vector<PartDef>& out) {
    const Json* parts = c.array(owner, at, "parts", false);
    if (!parts) return;
    for (std::size_t i = 0; i < parts->size(); ++i) {
        const std::string p = at + "/parts/" + std::to_string(i);
        const Json& part = (*parts)[i];
        if (!part.is_object()) {
            c.problem(p, "expected an object, got " + JsonChecker::describe(part));
            continue;
        }
        c.no_unknown_keys(part, p, {"kind", "mesh", "count", "at", "size_mm", "collision", "tilt_deg", "cup_deg", "whorls", "colour_variation",
                                    "shape", "width_mm", "tip", "fold_deg"});
        const auto kind = c.choice(part, p, "kind", {"petal", "leaf"});
        PartDef def{};
        def.kind = kind == "leaf" ? components::PartKind::leaf : components::PartKind::petal;
        def.mesh = c.string(part, p, "mesh", false).value_or("");
        def.count = static_cast<std::uint32_t>(c.integer(part, p, "count", 1, 64, false).value_or(1));
        def.position_along_stem = c.number(part, p, "at", {0, 1}).value_or(0);
        def.size_m = c.number(part, p, "size_mm", {1, 1000, true}).value_or(0) * mm;
        def.collision = collision_of(c.choice(part, p, "collision", {"active", "passive", "inactive"}))
                            .value_or(CollisionClass::inactive);
        def.tilt_rad = c.number(part, p, "tilt_deg", {-90, 90}, false).value_or(0) * deg;
        def.cup_rad = c.number(part, p, "cup_deg", {-120, 120}, false).value_or(0) * deg;
        def.whorls = static_cast<std::uint32_t>(c.integer(part, p, "whorls", 1, 8, false).value_or(1));
        def.colour_variation = c.number(part, p, "colour_variation", {0, 0.5}, false).value_or(0);
        read_part_shape(c, part, p, def);
        out.push_back(def);
    }
}

// A species' twigs stop here: a branch of a branch of a branch of a branch. And at so many in all (a
// tree of twigs costs the haptic tick its points).
constexpr int deepest_branch = 4;
constexpr std::uint32_t most_twigs = 120;

// How many twigs these branches make, their twigs' twigs included.
std::uint64_t twig_count(const std::vector<BranchDef>& branches) {
    std::uint64_t n = 0;
    for (const auto& b : branches) n += b.count * (1 + twig_count(b.branches));
    return n;
}

void read_branches(JsonChecker& c, const Json& owner, const std::string& at, int depth, std::vector<BranchDef>& out) {
    const Json* branches = c.array(owner, at, "branches", false);
    if (!branches) return;
    if (depth >= deepest_branch) {
        c.problem(at + "/branches", "twigs go at most " + std::to_string(deepest_branch) + " deep (a branch of a branch of a branch of a branch)");
        return;
    }
    for (std::size_t i = 0; i < branches->size(); ++i) {
        const std::string p = at + "/branches/" + std::to_string(i);
        const Json& branch = (*branches)[i];
        if (!branch.is_object()) {
            c.problem(p, "expected an object, got " + JsonChecker::describe(branch));
            continue;
        }
        c.no_unknown_keys(branch, p, {"count", "at", "every", "angle_deg", "azimuth_deg", "turn_deg", "shrink", "length_mm", "diameter_mm",
                                      "segments", "mass_g", "rest_bend_deg", "parts", "branches"});
        BranchDef def;
        def.count = static_cast<std::uint32_t>(c.integer(branch, p, "count", 1, 32, false).value_or(1));
        def.position_along_parent = c.number(branch, p, "at", {0, 1}).value_or(0.5);
        def.spacing = c.number(branch, p, "every", {0, 1}, false).value_or(0.0);
        def.angle_rad = c.number(branch, p, "angle_deg", {0, 150}).value_or(0) * deg;
        def.azimuth_rad = c.number(branch, p, "azimuth_deg", {-360, 360}, false).value_or(0) * deg;
        def.turn_rad = c.number(branch, p, "turn_deg", {-360, 360}, false).value_or(137.5) * deg;
        def.shrink = c.number(branch, p, "shrink", {0, 0.9}, false).value_or(0);
        def.length_m = c.number(branch, p, "length_mm", {5, 3000}).value_or(0) * mm;
        def.diameter_m = c.number(branch, p, "diameter_mm", {0.3, 100}).value_or(0) * mm;
        def.segments = static_cast<std::uint32_t>(c.integer(branch, p, "segments", 2, 60).value_or(2));
        def.mass_kg = c.number(branch, p, "mass_g", {0.001, 5000, true}).value_or(0) * 1e-3;
        // Up toward the light (positive) or down, weeping (negative).
        def.rest_bend_rad = c.number(branch, p, "rest_bend_deg", {-180, 180}, false).value_or(0) * deg;
        const double last = def.position_along_parent + def.spacing * (def.count - 1);
        if (branch.contains("at") && branch.contains("every") && last > 1.0 + 1e-9) {
            c.problem(p + "/every", "its " + std::to_string(def.count) + " twigs from " + JsonChecker::describe(branch["at"]) + " every " +
                                        JsonChecker::describe(branch["every"]) + " run past the parent's top (1)");
        }
        read_parts(c, branch, p, def.parts);
        read_branches(c, branch, p, depth + 1, def.branches);
        out.push_back(std::move(def));
    }
}

void read_resistance(JsonChecker& c, const Json& root, SpeciesDef& out) {
    const Json* r = c.object(root, "", "resistance");
    if (!r) return;
    const std::string p = "/resistance";
    const auto model = c.choice(*r, p, "model", {"hard_eq6", "soft_table"});
    if (model == "hard_eq6") {
        c.no_unknown_keys(*r, p, {"model", "cortex_tip_gf_per_mm", "cortex_trunk_gf_per_mm", "pith_tip_gf_per_mm",
                                  "pith_trunk_gf_per_mm", "pith_diameter_mm"});
        HardResistance h{};
        h.cortex_tip_n_per_m = c.number(*r, p, "cortex_tip_gf_per_mm", {0, 1e5}).value_or(0) * gf_per_mm;
        h.cortex_trunk_n_per_m = c.number(*r, p, "cortex_trunk_gf_per_mm", {0, 1e5}).value_or(0) * gf_per_mm;
        h.pith_tip_n_per_m = c.number(*r, p, "pith_tip_gf_per_mm", {0, 1e5}).value_or(0) * gf_per_mm;
        h.pith_trunk_n_per_m = c.number(*r, p, "pith_trunk_gf_per_mm", {0, 1e5}).value_or(0) * gf_per_mm;
        h.pith_diameter_m = c.number(*r, p, "pith_diameter_mm", {0, 100}).value_or(0) * mm;
        if (out.diameter_m > 0 && h.pith_diameter_m >= out.diameter_m) {
            c.problem(p + "/pith_diameter_mm", "must be smaller than /stem/diameter_mm");
        }
        out.hard = h;
        if (out.branch != BranchKind::hard) c.problem(p + "/model", "\"hard_eq6\" needs \"branch\": \"hard\"");
    } else if (model == "soft_table") {
        c.no_unknown_keys(*r, p, {"model", "gf_per_mm_by_insertion", "max_per_pin_gf_by_insertion"});
        SoftResistance s{};
        const auto per_mm = c.numbers(*r, p, "gf_per_mm_by_insertion", {0, 1e5}, 1);
        const auto per_pin = c.numbers(*r, p, "max_per_pin_gf_by_insertion", {0, 1e6}, 1, false);
        if (per_mm) for (double v : *per_mm) s.n_per_m_by_insertion.push_back(v * gf_per_mm);
        if (per_pin) for (double v : *per_pin) s.max_per_pin_n_by_insertion.push_back(v * gram_force_n);
        if (per_mm && per_pin && per_pin->size() != per_mm->size()) {
            c.problem(p + "/max_per_pin_gf_by_insertion", "expected as many values as gf_per_mm_by_insertion (" +
                                                              std::to_string(per_mm->size()) + ")");
        }
        out.soft = s;
        if (out.branch != BranchKind::soft) c.problem(p + "/model", "\"soft_table\" needs \"branch\": \"soft\"");
    }
}

void read_deterioration(JsonChecker& c, const Json& root, SpeciesDef& out) {
    const Json* d = c.object(root, "", "deterioration");
    if (!d) return;
    const std::string p = "/deterioration";
    const std::vector<std::string> plain = {"paper_baseline", "table_hold_last", "none"};
    std::vector<std::string> all = plain;
    all.push_back("extended");
    const auto model = c.choice(*d, p, "model", all);
    out.deterioration.model = model.value_or("");
    std::string base = out.deterioration.model;
    if (model == "extended") {
        c.no_unknown_keys(*d, p, {"model", "base", "terms", "applies_to", "fitted_from", "notes"});
        base = c.choice(*d, p, "base", plain).value_or("");
        if (d->contains("applies_to")) out.deterioration.applies_to = c.choice(*d, p, "applies_to", {"push_and_hold", "push"}).value_or("push_and_hold");
        out.deterioration.base_model = base;
        if (const Json* terms = c.array(*d, p, "terms")) {
            for (std::size_t i = 0; i < terms->size(); ++i) {
                const std::string tp = p + "/terms/" + std::to_string(i);
                const Json& t = (*terms)[i];
                if (!t.is_object()) {
                    c.problem(tp, "expected an object, got " + JsonChecker::describe(t));
                    continue;
                }
                c.no_unknown_keys(t, tp, {"covariate", "form", "coefficient", "scale", "origin", "range", "category", "times", "applies_to"});
                // A term of its own on what holds the stem at rest; otherwise as the block's applies_to says.
                const bool hold_only = t.contains("applies_to") && c.choice(t, tp, "applies_to", {"hold", "push_and_hold"}).value_or("") == "hold";
                components::DeteriorationTerm term{};
                term.covariate = c.string(t, tp, "covariate").value_or("");
                term.form = c.choice(t, tp, "form", {"constant", "linear", "log", "saturating", "power", "step", "peaked", "category"}).value_or("");
                // An interaction's coefficient is per unit of its second covariate too (a fraction's units
                // are small): it gets the room the factor's own clamp (e^+-5) bounds anyway.
                term.coefficient = c.number(t, tp, "coefficient", t.contains("times") ? NumberRange{-1e6, 1e6} : NumberRange{-50, 50}).value_or(0);
                // Where a covariate is centred and how wide it runs: a lab's columns include Unix
                // timestamps (1.7e9 s) and readings in any unit, so any finite value (the basis is
                // computed from x - origin, which stays small whatever the origin).
                term.scale = c.number(t, tp, "scale", {-term_value_limit, term_value_limit}, false).value_or(0);
                term.origin = c.number(t, tp, "origin", {-term_value_limit, term_value_limit}, false).value_or(0);
                if (t.contains("range")) {
                    const auto range = c.numbers(t, tp, "range", {-term_value_limit, term_value_limit}, 2);
                    if (range && range->size() != 2) c.problem(tp + "/range", "expected [low, high]");
                    else if (range && (*range)[0] > (*range)[1]) c.problem(tp + "/range", "expected low <= high");
                    else if (range) {
                        term.range_low = (*range)[0];
                        term.range_high = (*range)[1];
                    }
                }
                term.category = c.string(t, tp, "category", term.form == "category").value_or("");
                if (t.contains("times")) {
                    // An interaction: this term's basis times (that covariate - origin).
                    const std::string xp = tp + "/times";
                    if (const Json* times = c.object(t, tp, "times")) {
                        c.no_unknown_keys(*times, xp, {"covariate", "origin", "range"});
                        term.times_covariate = c.string(*times, xp, "covariate").value_or("");
                        term.times_origin = c.number(*times, xp, "origin", {-term_value_limit, term_value_limit}, false).value_or(0);
                        // The range is required: it is where a world without the covariate takes it (its centre).
                        if (!times->contains("range")) c.problem(xp + "/range", "missing: give [low, high], the values the interaction was fitted over");
                        else {
                            const auto range = c.numbers(*times, xp, "range", {-term_value_limit, term_value_limit}, 2);
                            if (range && range->size() != 2) c.problem(xp + "/range", "expected [low, high]");
                            else if (range && (*range)[0] > (*range)[1]) c.problem(xp + "/range", "expected low <= high");
                            else if (range) {
                                term.times_low = (*range)[0];
                                term.times_high = (*range)[1];
                            }
                        }
                    }
                    if (term.form == "category" || term.form == "constant") c.problem(xp, "an interaction multiplies a numeric term, not a " + term.form);
                }
                (hold_only ? out.deterioration.hold_terms : out.deterioration.terms).push_back(term);
            }
        }
    } else {
        c.no_unknown_keys(*d, p, {"model"});
    }
    if ((base == "paper_baseline" || base == "table_hold_last") && !out.soft && out.branch == BranchKind::soft) {
        c.problem(p + "/model", "\"" + base + "\" needs a \"soft_table\" resistance");
    }
    if (base == "paper_baseline" && out.soft && out.soft->n_per_m_by_insertion.size() < 3) {
        c.problem("/resistance/gf_per_mm_by_insertion", "\"paper_baseline\" averages insertions 3 onwards: give at least 3 values");
    }
}

void read_breakage(JsonChecker& c, const Json& root, SpeciesDef& out) {
    const Json* b = c.object(root, "", "breakage");
    if (!b) return;
    const std::string p = "/breakage";
    c.no_unknown_keys(*b, p, {"model", "probability_by_insertion", "broken_holding_factor", "broken_seat_loss_mm"});
    out.breakage.model = c.choice(*b, p, "model", {"hazard_by_insertion", "none"}).value_or("");
    if (out.breakage.model == "hazard_by_insertion") {
        out.breakage.probability_by_insertion = c.numbers(*b, p, "probability_by_insertion", {0, 1}, 1).value_or(std::vector<double>{});
        out.breakage.broken_holding_factor = c.number(*b, p, "broken_holding_factor", {0, 1}).value_or(1);
        out.breakage.broken_seat_loss_m = c.number(*b, p, "broken_seat_loss_mm", {0, 100}).value_or(0) * mm;
    } else {
        out.breakage.broken_holding_factor = 1.0;
    }
}

void read_look(JsonChecker& c, const Json& root, SpeciesDef& out) {
    const bool hard = out.branch == BranchKind::hard;
    out.stem_colour = hard ? glm::vec3(0.36f, 0.24f, 0.16f) : glm::vec3(0.28f, 0.5f, 0.18f);
    out.petal_colour = {0.95f, 0.78f, 0.12f};
    out.leaf_colour = {0.22f, 0.48f, 0.16f};
    out.head_colour = {0.3f, 0.18f, 0.07f};
    const Json* look = c.object(root, "", "look", false);
    if (!look) return;
    const std::string p = "/look";
    c.no_unknown_keys(*look, p, {"stem", "petal", "leaf", "head"});
    for (auto [key, target] : {std::pair{"stem", &out.stem_colour}, std::pair{"petal", &out.petal_colour}, std::pair{"leaf", &out.leaf_colour},
                               std::pair{"head", &out.head_colour}}) {
        const auto rgb = c.numbers(*look, p, key, {0, 1}, 3, false);
        if (!rgb) continue;
        if (rgb->size() != 3) {
            c.problem(p + "/" + key, "expected [r, g, b], got " + std::to_string(rgb->size()) + " numbers");
            continue;
        }
        *target = glm::vec3(static_cast<float>((*rgb)[0]), static_cast<float>((*rgb)[1]), static_cast<float>((*rgb)[2]));
    }
}

} // namespace

bool valid_species_id(std::string_view id) noexcept {
    return !id.empty() && id.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-") == std::string_view::npos;
}

Result<SpeciesDef> parse_species(std::string_view text, const std::string& label) {
    JsonChecker c(label);
    const auto root = c.parse_object(text);
    if (!root) return c.error();
    c.no_unknown_keys(*root, "", {"format", "id", "name", "branch", "stem", "head", "parts", "branches", "resistance",
                                  "deterioration", "breakage", "look", "notes"});
    SpeciesDef out{};
    const auto format = c.string(*root, "", "format");
    if (format && *format != "ikebana-species/1") {
        c.problem("/format", "expected \"ikebana-species/1\", got \"" + *format + "\"");
    }
    out.id = c.string(*root, "", "id").value_or("");
    if (!out.id.empty() && !valid_species_id(out.id)) {
        c.problem("/id", "expected lower-case letters, digits, '-' or '_', got \"" + out.id + "\"");
    }
    out.name = c.string(*root, "", "name", false).value_or(out.id);
    out.branch = c.choice(*root, "", "branch", {"soft", "hard"}) == "hard" ? BranchKind::hard : BranchKind::soft;
    read_stem(c, *root, out);
    read_head(c, *root, out);
    read_parts(c, *root, "", out.parts);
    read_branches(c, *root, "", 0, out.branches);
    if (const auto twigs = twig_count(out.branches); twigs > most_twigs) {
        c.problem("/branches", "makes " + std::to_string(twigs) + " twigs in all, more than " + std::to_string(most_twigs) + ": each is simulated at 1 kHz");
    }
    read_resistance(c, *root, out);
    read_deterioration(c, *root, out);
    read_breakage(c, *root, out);
    read_look(c, *root, out);
    if (!c.ok()) return c.error();
    return out;
}

Result<SpeciesDef> load_species_file(const std::filesystem::path& path) {
    auto text = assets::read_text_file(path);
    if (!text) return std::move(text).error();
    auto species = parse_species(*text, path.filename().string());
    if (!species) return species;
    species->file = path;
    // A mesh beside the species file is that one; otherwise the assets folder's (the name stays as
    // written, and the one who draws it looks there). Where it is not, `species check` says where it looked.
    // A mesh outside the species file's folder and the assets folder is refused here (named_from).
    std::string outside;
    const auto beside = [&](std::string& mesh, const std::string& field) {
        if (mesh.empty()) return;
        const auto found = named_from(path, mesh);
        if (!found && found.error().code == ErrorCode::invalid_argument && outside.empty()) outside = path.filename().string() + ": " + field + ": " + found.error().message;
        std::error_code ec;
        if (!found || *found == (asset_dir() / mesh).lexically_normal()) return;
        const auto whole = std::filesystem::absolute(*found, ec);
        mesh = ec ? found->string() : whole.string();
    };
    beside(species->head_mesh, "/head/mesh");
    for (std::size_t i = 0; i < species->parts.size(); ++i) beside(species->parts[i].mesh, "/parts/" + std::to_string(i) + "/mesh");
    const auto twig_meshes = [&](auto& self, std::vector<BranchDef>& branches, const std::string& at) -> void {
        for (std::size_t i = 0; i < branches.size(); ++i) {
            const std::string p = at + "/branches/" + std::to_string(i);
            for (std::size_t k = 0; k < branches[i].parts.size(); ++k) beside(branches[i].parts[k].mesh, p + "/parts/" + std::to_string(k) + "/mesh");
            self(self, branches[i].branches, p);
        }
    };
    twig_meshes(twig_meshes, species->branches, "");
    if (!outside.empty()) return make_error(ErrorCode::parse_error, outside);
    return species;
}

Result<SpeciesDef> load_species(const std::string& id_or_path) {
    if (id_or_path.find('/') != std::string::npos || id_or_path.ends_with(".json")) return load_species_file(id_or_path);
    return load_species_file(asset_dir() / "species" / (id_or_path + ".json"));
}

} // namespace ikebana::game
