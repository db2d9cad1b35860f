#include "game/world/lesson_scene.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numbers>

#include "game/asset_paths.hpp"
#include "game/kenzan/kenzan_layout.hpp"
#include "game/species/species.hpp"
#include "game/lesson/role_colours.hpp"
#include "game/world/world.hpp"
#include "systems/presentation/draw_list.hpp"

namespace ikebana::game {

namespace {

// How far a branch's twigs reach out from it (each at its fork's angle, its own twigs beyond).
double twig_reach_m(const std::vector<BranchDef>& branches) {
    double reach = 0.0;
    for (const auto& b : branches) reach = std::max(reach, b.length_m * std::sin(b.angle_rad) + twig_reach_m(b.branches));
    return reach;
}
constexpr double wall_m = 0.006; // as World builds containers
}

Result<KenzanFootprint> footprint_of(const LessonDef& l) {
    auto k = load_kenzan(l.kenzan_layout);
    if (!k) return std::move(k).error();
    return KenzanFootprint{{(k->columns + 1) * k->pitch_m, (k->rows + 1) * k->pitch_m}, k->base_thickness_m};
}

Result<SceneDef> scene_for_lesson(const LessonDef& l) {
    if (l.scoring == "sample") {
        const auto file = named_from(l.file, l.scene);
        if (!file) return make_error(file.error().code, l.file.filename().string() + ": /scene: " + file.error().message);
        return load_scene(*file);
    }
    const auto kenzan = load_kenzan(l.kenzan_layout);
    if (!kenzan) return std::move(kenzan).error();
    SceneDef s{};
    s.file = l.file;
    s.seed = 1;
    s.gravity_m_s2 = {0, 0, -9.80665};
    s.table_height_m = 0.0;
    s.container = l.container;
    // The kenzan at the origin (where the camera looks), the container around it.
    s.container_centre_m = -l.kenzan_offset_m;
    const double rim = wall_m + l.container.depth_m;
    const double floor = l.container.shape == ContainerShape::vase ? rim - 0.03 : wall_m;
    s.kenzan_layout = l.kenzan_layout;
    s.kenzan_position_m = {0.0, 0.0, floor + kenzan->base_thickness_m};
    // The materials lie across the table in front of the container, longest at the back.
    struct Lying {
        double length_m;
        double reach_m; // how far its twigs spread across it, lying flat
        FlowerPlacement placement;
    };
    std::vector<Lying> lying;
    for (const auto& m : l.materials) {
        const auto species = load_species(m.species);
        if (!species) return std::move(species).error();
        const double length = m.length_m > 0.0 ? m.length_m : species->length_m;
        const double reach = twig_reach_m(species->branches);
        for (std::uint32_t i = 0; i < m.count; ++i) lying.push_back({length, reach, FlowerPlacement{m.species, Placement::lying, {}, {1, 0, 0}, 0.0, length}});
    }
    std::stable_sort(lying.begin(), lying.end(), [](const auto& a, const auto& b) { return a.length_m > b.length_m; });
    const double front = s.container_centre_m.y - 0.5 * l.container.front_to_back_m - wall_m;
    // A branch's twigs lie flat on both sides of it: it lies far enough from the container that they
    // stay out of it (over the materials in front of it they may lie, as on a real table).
    double y = front - 0.01;
    double first_row = front - 0.04;
    for (auto& m : lying) {
        y = std::min(y - 0.03, front - 0.04 - m.reach_m);
        if (&m == &lying.front()) first_row = y;
        m.placement.base_m = {-0.5 * m.length_m, y, 0.0};
        s.flowers.push_back(m.placement);
    }
    // The hands just above the materials' right and left ends, over their middle row.
    const double hands_y = std::min(front - 0.08, 0.5 * (first_row + y));
    s.hands.push_back({0, {-0.15, hands_y, 0.08}, 0.02, ""});
    s.hands.push_back({1, {0.15, hands_y, 0.08}, 0.02, ""});
    // Far enough back to see the tallest stem and the materials.
    double tallest = 0.0;
    for (std::size_t i = 0; i < l.stems.size(); ++i) tallest = std::max(tallest, nominal_length_m(l, i));
    const double height = std::max(0.3, tallest + rim);
    // The view's middle a little above the form's middle: the HUD's panel covers the top of the view.
    // Sideways, a little toward the model that G sets behind and right of the container.
    const double aside = 0.1 * l.container.width_m;
    // Branches with twigs lie further out: the view's middle moves toward them and the camera back, so
    // that the nearest material is in view (the table's depth the materials take beyond 0.1 m).
    const double materials_depth = std::max(0.0, front - y - 0.13);
    const double middle = front - 0.05 - 0.5 * materials_depth;
    s.display.camera_target_m = glm::dvec3{aside, middle, 0.4 * height};
    s.display.camera_position_m = glm::dvec3{aside, middle - 1.7 * height - 1.2 * materials_depth, 1.0 * height + 0.6 * materials_depth};
    s.display.screen_distance_m = glm::length(*s.display.camera_position_m - *s.display.camera_target_m);
    s.rates_hz = {{"haptic", 1000}, {"position_estimate", 100}, {"position_check", 16}, {"render", 30}};
    return s;
}

glm::dvec2 bottom_for(glm::dvec2 base, glm::dvec3 want, double in_pins) {
    if (want.z < 0.2) return base;
    return base - glm::dvec2{want.x, want.y} * (in_pins / want.z);
}

std::optional<double> rim_tilt_rad(const components::Container& c, glm::dvec3 bottom, double azimuth_rad, double reach_m, double radius_m) {
    if (c.floor_z_m > c.base_z_m + c.wall_m + 1e-6) return std::nullopt; // a vase
    const glm::dvec3 way = lesson_direction(0.5 * 3.14159265358979323846, azimuth_rad);
    const glm::dvec2 u{way.x, way.y};
    const glm::dvec2 b = glm::dvec2(bottom) - c.centre_m;
    const double to_wall = distance_to_wall_m(c.round, c.half_extent_m + glm::dvec2{0.5 * c.wall_m}, b, u);
    const double rise = c.rim_z_m + radius_m + 0.002 - bottom.z;
    if (to_wall >= reach_m || rise <= 0.0) return std::nullopt;
    return std::atan2(to_wall, rise);
}

std::optional<double> rim_held_tilt_rad(const ArrangementStem& stem, const components::FrameSnapshot& frame, double radius_m) {
    if (stem.path_m.size() == 2 || !frame.container || !frame.kenzan) return std::nullopt;
    const glm::dvec3 want = lesson_direction(stem.tilt_rad, stem.azimuth_rad);
    const double pin_height = frame.kenzan->pin_height_m();
    const glm::dvec3 bottom = frame.kenzan->origin_m + glm::dvec3(bottom_for(stem.base_m, want, pin_height), 0.0);
    const auto clears = rim_tilt_rad(*frame.container, bottom, stem.azimuth_rad, stem.length_m + in_pins_along_m(pin_height, stem.tilt_rad), radius_m);
    if (clears && *clears - rim_margin_rad < stem.tilt_rad) return *clears - rim_margin_rad;
    return std::nullopt;
}

Arrangement measure_arrangement(const components::FrameSnapshot& frame) {
    Arrangement a;
    if (!frame.kenzan) return a;
    const auto& k = *frame.kenzan;
    if (frame.container) a.kenzan_offset_m = glm::dvec2(k.origin_m) - frame.container->centre_m;
    std::vector<bool> held(frame.flowers.size(), false);
    for (const auto& h : frame.hands) {
        if (h.held_flower >= 0 && static_cast<std::size_t>(h.held_flower) < held.size()) held[static_cast<std::size_t>(h.held_flower)] = true;
    }
    const double pin_top = k.origin_m.z + k.pin_height_m();
    for (std::size_t i = 0; i < frame.flowers.size(); ++i) {
        const auto& f = frame.flowers[i];
        if (held[i] || (!f.in_kenzan && !f.fallen) || f.points_m.size() < 2) continue;
        const auto& x = f.points_m;
        // Where it enters the pins: its line's crossing of the pins' tops (its bottom if that is above them).
        glm::dvec3 entry = x.front();
        std::size_t from = 1;
        for (std::size_t j = 1; j < x.size(); ++j) {
            if (x[j - 1].z < pin_top && x[j].z >= pin_top) {
                const double t = (pin_top - x[j - 1].z) / (x[j].z - x[j - 1].z);
                entry = x[j - 1] + (x[j] - x[j - 1]) * t;
                from = j;
                break;
            }
        }
        ArrangementStem s;
        s.species = f.species;
        s.base_m = glm::dvec2(entry) - glm::dvec2(k.origin_m);
        double length = glm::length(x[from] - entry);
        for (std::size_t j = from + 1; j < x.size(); ++j) length += glm::length(x[j] - x[j - 1]);
        s.length_m = length;
        const glm::dvec3 chord = x.back() - entry;
        const double c = glm::length(chord);
        s.tilt_rad = c > 0.0 ? std::acos(std::clamp(chord.z / c, -1.0, 1.0)) : 0.0;
        s.azimuth_rad = std::atan2(-chord.x, -chord.y); // 0 toward the viewer (-y), + to the viewer's left (-x)
        s.standing = f.in_kenzan && !f.fallen;
        for (std::size_t j = from; j < x.size(); ++j) s.path_m.push_back(x[j] - glm::dvec3(k.origin_m));
        // Where its leaves meet the bark: the stem point each hangs on (a leaf sits on the bark there).
        const auto leaves_on = [&](const std::vector<glm::dvec3>& points, const std::vector<components::Part>& parts) {
            for (const auto& part : parts) {
                if (part.kind == components::PartKind::leaf && part.stem_point < points.size()) s.leaf_heights_m.push_back(points[part.stem_point].z - k.origin_m.z);
            }
        };
        leaves_on(x, f.parts);
        for (const auto& twig : f.twigs) leaves_on(twig.points_m, twig.parts);
        a.stems.push_back(std::move(s));
    }
    return a;
}

} // namespace ikebana::game

namespace ikebana::game {

namespace {
// Held further than this from its bottom end (and than a third of its length), a stem is taken again.
constexpr double far_from_end_m = 0.1;
// The gauge's band for a supporting stem, round the model's lean (no school scores a jushi's angle).
constexpr double jushi_guide_tilt_rad = 15.0 * 3.14159265358979323846 / 180.0;
constexpr double jushi_guide_azimuth_rad = 30.0 * 3.14159265358979323846 / 180.0;

// Where on the kenzan, as the tail of "lower it into ...": a role placed anywhere read "into anywhere on
// the kenzan of the kenzan".
std::string on_kenzan_words(KenzanRegion r) { return r == KenzanRegion::any ? "the kenzan" : region_words(r) + " of the kenzan"; }

// The part of the kenzan a point of its face (from its centre, x right, y away) is in: thirds each way.
KenzanRegion region_of(glm::dvec2 at, glm::dvec2 size) {
    const int col = at.x < -size.x / 6.0 ? 0 : at.x > size.x / 6.0 ? 2 : 1;
    const int row = at.y < -size.y / 6.0 ? 0 : at.y > size.y / 6.0 ? 2 : 1;
    constexpr KenzanRegion table[3][3] = {{KenzanRegion::front_left, KenzanRegion::front, KenzanRegion::front_right},
                                          {KenzanRegion::left, KenzanRegion::centre, KenzanRegion::right},
                                          {KenzanRegion::back_left, KenzanRegion::back, KenzanRegion::back_right}};
    return table[row][col];
}
} // namespace

namespace {
// From its bottom end along the stem to point i.
double along_to(const std::vector<glm::dvec3>& x, std::size_t i) {
    double s = 0.0;
    for (std::size_t k = 1; k <= i && k < x.size(); ++k) s += glm::length(x[k] - x[k - 1]);
    return s;
}
double stem_length(const std::vector<glm::dvec3>& x) { return x.empty() ? 0.0 : along_to(x, x.size() - 1); }
bool far_from_bottom(const std::vector<glm::dvec3>& x, std::size_t i) { return along_to(x, i) > std::max(far_from_end_m, 0.35 * stem_length(x)); }
} // namespace

std::optional<glm::dvec3> bottom_grip_for(const components::FrameSnapshot& frame, std::size_t hand, double along_m) {
    const auto reach = systems::stem_in_reach(frame, hand);
    if (!reach) return std::nullopt;
    const auto& f = frame.flowers[reach->flower];
    if (f.in_kenzan || f.points_m.size() < 3) return std::nullopt;
    // Taken near its bottom but on the part C will cut off, the hand would hold the piece that comes
    // off (a trainee took a chrysanthemum 100 mm up and C refused to cut it for a 59 mm jushi): it
    // takes it above that part instead.
    const bool on_cut_off = along_m > 0.06 + 1e-9 && along_to(f.points_m, reach->point) < along_m - 0.02;
    if (!far_from_bottom(f.points_m, reach->point) && !on_cut_off) return std::nullopt;
    // The point nearest 60 mm along the stem: near its end, and above what C usually cuts off (a grip
    // 30 mm up was cut away with the 42 mm a chrysanthemum lost for hikae, and the hand held nothing).
    std::size_t best = 0;
    for (std::size_t i = 1; i < f.points_m.size(); ++i) {
        if (std::abs(along_to(f.points_m, i) - along_m) < std::abs(along_to(f.points_m, best) - along_m)) best = i;
    }
    return f.points_m[best];
}

double grip_along_m(const LessonDef& l, const KenzanFootprint& footprint, const components::FrameSnapshot& frame, std::size_t hand) {
    constexpr double near_end_m = 0.06;
    const auto reach = hand < 2 ? systems::stem_in_reach(frame, hand) : std::nullopt;
    if (!reach || l.scoring != "form") return near_end_m;
    // What C would keep of it once held (the same advice the panel gives then).
    components::FrameSnapshot held = frame;
    held.hands[hand].holding = true;
    held.hands[hand].held_flower = static_cast<std::int32_t>(reach->flower);
    const auto advice = advise_held_stem(l, footprint, held, hand);
    const double cut_m = stem_length(frame.flowers[reach->flower].points_m) - advice.keep_length_m;
    return advice.keep_length_m > 0.0 && cut_m > 0.0 ? std::max(near_end_m, cut_m + 0.03) : near_end_m;
}

std::string role_heading_for(const LessonDef& l, const KenzanFootprint& footprint, const components::FrameSnapshot& frame, const std::string& species) {
    const auto placed = score_form(l, measure_arrangement(frame), footprint);
    for (const auto& m : l.stems) {
        bool played = false;
        if (placed) {
            for (const auto& s : placed->arrangement.stems) played = played || (s.standing && s.role == m.role);
        }
        if (played) continue;
        if (!m.species.empty() && std::find(m.species.begin(), m.species.end(), species) == m.species.end()) continue;
        return m.role;
    }
    // No main role left for it: a supporting stem, where the form has them (as advise_held_stem says
    // once it is held; the press was named "no role of the form is left for it").
    const Arrangement model = model_arrangement(l, footprint);
    if (std::any_of(model.stems.begin(), model.stems.end(), [](const ArrangementStem& s) { return s.role == "supporting"; })) return "a supporting stem (jushi)";
    return "";
}

namespace {

// Two directions' difference about the vertical, in (-pi, pi].
double angle_between_rad(double a, double b) { return std::remainder(a - b, 2.0 * std::numbers::pi); }

// The held stem's leaves that would stand in the water once it is cut to `keep_m` and pushed into the
// pins leaning `tilt_rad`: a line saying so, or nothing (no such leaves, or a lesson without the rule).
std::string low_leaves_line(const LessonDef& l, const KenzanFootprint& footprint, const components::FlowerStatus& f, double length_m, double keep_m,
                            double tilt_rad) {
    if (std::none_of(l.rules.begin(), l.rules.end(), [](const RuleDef& r) { return r.kind == RuleKind::no_leaves_under_water; })) return "";
    const auto& x = f.points_m;
    const double cut = std::max(0.0, length_m - keep_m);
    const double water = water_level_m(l, footprint);
    std::size_t low = 0;
    for (const auto& part : f.parts) {
        if (part.kind != components::PartKind::leaf || part.stem_point >= x.size()) continue;
        double along = 0.0;
        for (std::size_t i = 1; i <= part.stem_point; ++i) along += glm::length(x[i] - x[i - 1]);
        if (along >= cut && (along - cut) * std::cos(tilt_rad) < water) ++low;
    }
    if (low == 0) return "";
    char text[200];
    std::snprintf(text, sizeof text, "%zu lea%s would stand in the water (they rot): Tab, the other hand's cube on each, P strips it", low, low == 1 ? "f" : "ves");
    return text;
}
} // namespace

HeldStemAdvice advise_held_stem(const LessonDef& l, const KenzanFootprint& footprint, const components::FrameSnapshot& frame, std::size_t hand) {
    HeldStemAdvice advice;
    if (hand >= 2 || !frame.kenzan || l.scoring != "form") return advice;
    const auto& h = frame.hands[hand];
    if (h.held_flower < 0 || static_cast<std::size_t>(h.held_flower) >= frame.flowers.size()) return advice;
    const auto& f = frame.flowers[static_cast<std::size_t>(h.held_flower)];
    const auto& x = f.points_m;
    if (x.size() < 2) return advice;
    double length = 0.0;
    for (std::size_t i = 1; i < x.size(); ++i) length += glm::length(x[i] - x[i - 1]);
    const glm::dvec3 chord = x.back() - x.front();
    const double tilt = std::acos(std::clamp(glm::normalize(chord).z, -1.0, 1.0));
    const double azimuth = std::atan2(-chord.x, -chord.y);
    constexpr double deg = 180.0 / 3.14159265358979323846;
    char text[320];
    std::string species = f.species; // as a trainee reads it
    std::replace(species.begin(), species.end(), '_', ' ');
    std::snprintf(text, sizeof text, "holding a %s: %.0f mm long, %.0f° from vertical toward the %s", species.c_str(), length * 1e3, tilt * deg,
                  direction_words(azimuth).c_str());
    advice.lines.emplace_back(text);
    // Held far from its bottom end (a trainee takes a lying stem where the cursor happens to be), it
    // cannot be pushed into the pins: turning it swings the long end into the table.
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < x.size(); ++i) {
        if (glm::length(x[i] - h.position_m) < glm::length(x[nearest] - h.position_m)) nearest = i;
    }
    double held_from_bottom = 0.0;
    for (std::size_t i = 1; i <= nearest; ++i) held_from_bottom += glm::length(x[i] - x[i - 1]);
    // Far from the bottom it will have once C has cut it to `keep_m` (a stem taken above what C cuts
    // off for a jushi is held near its end once cut: a trainee was told to take it again by its end,
    // then that C would cut off the part in the hand).
    const auto held_far_after_cut = [&](double keep_m) {
        const double cut_m = keep_m > 0.0 ? std::max(0.0, length - keep_m) : 0.0;
        return held_from_bottom - cut_m > std::max(far_from_end_m, 0.35 * (length - cut_m));
    };
    bool held_far = held_far_after_cut(0.0);
    // Said under the first line when, cut as its role wants, it is still held far from its end.
    const auto finish = [&]() -> HeldStemAdvice {
        // In the pins at a lean they cannot hold: said while the hand still holds it, with the lean
        // they would hold there (supporting stems let go at 55° sank to 78° with no word). The weight's
        // moment grows about as the sine of the lean.
        if (f.in_kenzan && !f.fallen && f.gravity_moment_nm > f.holding_moment_nm && f.gravity_moment_nm > 0.0) {
            const double share = f.holding_moment_nm / f.gravity_moment_nm;
            const double holds_rad = std::asin(std::clamp(std::sin(tilt) * share, 0.0, 1.0));
            std::snprintf(text, sizeof text, "let go now and it sinks: at %.0f° the pins hold %.0f %% of what its weight asks; here they hold it to about %.0f° (lean it less, or push it deeper)",
                          tilt * deg, 100.0 * share, holds_rad * deg);
            advice.would_sink = text;
            advice.lines.insert(advice.lines.begin() + std::min<std::ptrdiff_t>(1, static_cast<std::ptrdiff_t>(advice.lines.size())), text);
        }
        if (held_far) {
            std::snprintf(text, sizeof text, "held %.0f mm from its bottom end: to push it in, let go and take it near that end", held_from_bottom * 1e3);
            advice.lines.insert(advice.lines.begin() + std::min<std::ptrdiff_t>(1, static_cast<std::ptrdiff_t>(advice.lines.size())), text);
        }
        return std::move(advice);
    };
    // The roles already played by standing stems, as the score assigns them.
    const auto placed = score_form(l, measure_arrangement(frame), footprint);
    std::optional<Arrangement> model;
    std::vector<std::string> played;
    if (placed) {
        for (const auto& s : placed->arrangement.stems) {
            if (s.standing && s.role != "supporting") played.push_back(s.role);
        }
    }
    for (std::size_t r = 0; r < l.stems.size(); ++r) {
        const auto& m = l.stems[r];
        if (std::find(played.begin(), played.end(), m.role) != played.end()) continue;
        if (!m.species.empty() && std::find(m.species.begin(), m.species.end(), f.species) == m.species.end()) continue;
        // The length: of the container, or of the stem that plays the role it follows, as it stands.
        double base = m.length_of.kind == LengthBase::Kind::container_height ? l.container.depth_m : l.container.size_m();
        // A target that follows another role says so (it changes with that stem, which the start
        // screen's figure cannot know).
        std::string follows;
        if (m.length_of.kind == LengthBase::Kind::role) {
            base = nominal_length_m(l, m.length_of.role);
            bool stands = false;
            if (placed) {
                for (const auto& s : placed->arrangement.stems) {
                    if (s.standing && s.role == l.stems[m.length_of.role].role) {
                        base = s.length_m;
                        stands = true;
                    }
                }
            }
            char ratio[96];
            std::snprintf(ratio, sizeof ratio, ": %.2g × %s%s", m.length_ratio.target, l.stems[m.length_of.role].role.c_str(),
                          stands ? " as yours stands" : " as the form has it");
            follows = ratio;
        }
        const double target = base * m.length_ratio.target;
        // What the pins take of it: more than their height when it leans (the score measures from
        // where its line crosses their tops), at the tilt the model stands it at (the rim may hold a
        // low stem a little higher than the form's figure).
        double lean_rad = m.tilt_rad.target;
        if (!model) model = model_arrangement(l, footprint);
        // The lean to aim for: the form's, or a degree inside the steepest at which it clears the
        // container's rim set where the form puts it (as the demonstration aims it: a trainee told
        // "75°" for hikae found the rim would not let it lean past 70).
        double aim_tilt_rad = m.tilt_rad.target;
        std::string rim_words;
        for (const auto& s : model->stems) {
            if (s.role != m.role) continue;
            lean_rad = s.path_m.size() == 2 ? 0.0 : s.tilt_rad;
            ArrangementStem as_asked = s; // at the form's lean and this stem's target length
            as_asked.tilt_rad = m.tilt_rad.target;
            as_asked.length_m = target;
            if (const auto held = rim_held_tilt_rad(as_asked, frame, 0.5 * f.diameter_m)) {
                aim_tilt_rad = *held;
                char why[96];
                std::snprintf(why, sizeof why, ", as far as the rim lets it of the form's %.0f°", m.tilt_rad.target * deg);
                rim_words = why;
                lean_rad = std::min(lean_rad, aim_tilt_rad);
            }
        }
        const double pins = in_pins_along_m(frame.kenzan->pin_height_m(), lean_rad);
        advice.role = m.role;
        advice.keep_length_m = target + pins;
        advice.gauge = HeldStemAdvice::Gauge{tilt, azimuth, m.tilt_rad.target, m.tilt_rad.tolerance,
                                             m.azimuth_rad ? std::optional<double>(m.azimuth_rad->target) : std::nullopt,
                                             m.azimuth_rad ? m.azimuth_rad->tolerance : 0.0, r};
        std::string lean = m.azimuth_rad ? " toward the " + direction_words(m.azimuth_rad->target) : "";
        held_far = held_far_after_cut(advice.keep_length_m);
        if (held_far) {
            advice.next_step = "let go (release the button) and take it again near its bottom end";
        } else if (length > advice.keep_length_m + 0.002) {
            std::snprintf(text, sizeof text, "press C to cut it for %s (to %.0f mm)", m.role.c_str(), advice.keep_length_m * 1e3);
            advice.next_step = text;
        } else {
            // Its tilt in the band, and the ring on the pins but outside the role's place: said while
            // it can still be moved (a trainee's stems all lost their place points with no word).
            const bool tilt_ok = std::abs(tilt - m.tilt_rad.target) <= m.tilt_rad.tolerance;
            const bool azimuth_ok = !m.azimuth_rad || std::abs(angle_between_rad(azimuth, m.azimuth_rad->target)) <= m.azimuth_rad->tolerance;
            if (tilt_ok && azimuth_ok) {
                // The step done moves Next on (at 69-70° with the ring green it still said "tilt it 69°").
                std::snprintf(text, sizeof text, "its lean is right (%.0f°): lower it straight down into %s, the ring green", tilt * deg,
                              on_kenzan_words(m.region).c_str());
            } else {
                std::snprintf(text, sizeof text, "tilt it %.0f°%s%s (Ctrl+drag), then lower it into %s", aim_tilt_rad * deg, lean.c_str(), rim_words.c_str(),
                              on_kenzan_words(m.region).c_str());
            }
            advice.next_step = text;
            if (const auto mark = systems::entry_mark(frame, hand); tilt_ok && mark && mark->good() && m.region != KenzanRegion::any) {
                const glm::dvec2 at = glm::dvec2(mark->at_m) - glm::dvec2(frame.kenzan->origin_m);
                if (outside_place_m(at, m.region, footprint) > 0.002) {
                    std::snprintf(text, sizeof text, "move it toward %s of the kenzan: the ring is in %s, %s goes in %s",
                                  region_words(m.region).c_str(), region_words(region_of(at, footprint.size_m)).c_str(), m.role.c_str(),
                                  region_words(m.region).c_str());
                    advice.next_step = text;
                }
            }
        }
        if (length > advice.keep_length_m + 0.002) {
            std::snprintf(text, sizeof text, "for %s: C cuts it to %.0f mm (%.0f above the kenzan%s; %.0f in the pins); then Ctrl+drag to tilt it %.0f°%s%s",
                          m.role.c_str(), advice.keep_length_m * 1e3, target * 1e3, follows.c_str(), pins * 1e3, aim_tilt_rad * deg, lean.c_str(), rim_words.c_str());
        } else {
            std::snprintf(text, sizeof text, "for %s (%.0f mm above the kenzan%s): tilt it %.0f° ±%.0f°%s (Ctrl+drag), put it in %s", m.role.c_str(),
                          target * 1e3, follows.c_str(), m.tilt_rad.target * deg, m.tilt_rad.tolerance * deg, lean.c_str(), on_kenzan_words(m.region).c_str());
        }
        advice.lines.emplace_back(text);
        if (const auto leaves = low_leaves_line(l, footprint, f, length, advice.keep_length_m, m.tilt_rad.target); !leaves.empty()) advice.lines.push_back(leaves);
        // A form whose stems rise as one line from the water (a shoka): a role that leans well away from
        // the line is bent first, as the demonstration does it (teacher.cpp).
        for (const auto& rule : l.rules) {
            if (rule.kind != RuleKind::one_line_at_water) continue;
            for (const auto& s : model_arrangement(l, footprint).stems) {
                if (s.role != m.role || s.path_m.size() != 2) continue;
                const double upper = lean_above_rise_rad(s);
                if (upper <= one_line_bend_beyond_rad) break;
                std::snprintf(text, sizeof text, "the form's stems rise as one line %.0f-%.0f mm above the water: first bend it about %.0f° %.0f mm from its cut end",
                              rule.min_m * 1e3, rule.max_m * 1e3, 5.0 * std::round(upper * deg / 5.0), (s.path_m[0].z + pins) * 1e3);
                advice.lines.emplace_back(text);
                advice.lines.emplace_back("to bend: Tab, take it with the other hand beside this one, Ctrl+drag rolls that wrist (further: a bend springs back part way)");
                break;
            }
        }
        return finish();
    }
    // A supporting stem (jushi): the next of the model arrangement's that no standing stem plays yet.
    std::size_t supporting_placed = 0;
    if (placed) {
        for (const auto& s : placed->arrangement.stems) supporting_placed += s.standing && s.role == "supporting" ? 1 : 0;
    }
    if (!model) model = model_arrangement(l, footprint);
    std::size_t seen = 0;
    for (const auto& s : model->stems) {
        if (s.role != "supporting" || seen++ < supporting_placed) continue;
        const double pins = in_pins_along_m(frame.kenzan->pin_height_m(), s.tilt_rad);
        advice.role = "supporting";
        advice.keep_length_m = s.length_m + pins;
        // The next step and the gauge as for a main role (a first-time trainee holding a fourth
        // chrysanthemum read jushi instructions above "no role is left for this stem"). The form
        // scores no jushi's angle: the band is the model's, a guide (+-15°, +-30°).
        const std::string place = on_kenzan_words(region_of(s.base_m, footprint.size_m));
        held_far = held_far_after_cut(advice.keep_length_m);
        if (held_far) {
            advice.next_step = "let go (release the button) and take it again near its bottom end";
        } else if (length > advice.keep_length_m + 0.002) {
            std::snprintf(text, sizeof text, "press C to cut it as a supporting stem (jushi, to %.0f mm)", advice.keep_length_m * 1e3);
            advice.next_step = text;
        } else {
            if (std::abs(tilt - s.tilt_rad) <= jushi_guide_tilt_rad && std::abs(angle_between_rad(azimuth, s.azimuth_rad)) <= jushi_guide_azimuth_rad) {
                std::snprintf(text, sizeof text, "its lean is right (%.0f°): lower it straight down into %s, the ring green", tilt * deg, place.c_str());
            } else {
                std::snprintf(text, sizeof text, "tilt it %.0f° toward the %s (Ctrl+drag), then lower it into %s", s.tilt_rad * deg,
                              direction_words(s.azimuth_rad).c_str(), place.c_str());
            }
            advice.next_step = text;
        }
        advice.gauge = HeldStemAdvice::Gauge{tilt, azimuth, s.tilt_rad, jushi_guide_tilt_rad, s.azimuth_rad, jushi_guide_azimuth_rad, l.stems.size()};
        if (length > advice.keep_length_m + 0.002) {
            std::snprintf(text, sizeof text, "as a supporting stem (jushi): C cuts it to %.0f mm (%.0f above the kenzan); then Ctrl+drag to tilt it %.0f° toward the %s",
                          advice.keep_length_m * 1e3, s.length_m * 1e3, s.tilt_rad * deg, direction_words(s.azimuth_rad).c_str());
        } else {
            std::snprintf(text, sizeof text, "as a supporting stem (jushi, %.0f mm above the kenzan): tilt it %.0f° toward the %s, low, in %s",
                          s.length_m * 1e3, s.tilt_rad * deg, direction_words(s.azimuth_rad).c_str(), place.c_str());
        }
        advice.lines.emplace_back(text);
        if (const auto leaves = low_leaves_line(l, footprint, f, length, advice.keep_length_m, s.tilt_rad); !leaves.empty()) advice.lines.push_back(leaves);
        return finish();
    }
    advice.lines.emplace_back("every role this species may play stands already: it can support (jushi), shorter than " +
                              (l.supporting.shorter_than_role ? l.stems[*l.supporting.shorter_than_role].role : std::string("the main stems")));
    return finish();
}

} // namespace ikebana::game

namespace ikebana::game {

namespace {
glm::mat4 rod(const glm::dvec3& p, const glm::dvec3& q, double radius) {
    const glm::dvec3 d = q - p;
    const glm::dvec3 axis = glm::length(d) > 1e-12 ? glm::normalize(d) : glm::dvec3{0, 0, 1};
    const glm::dvec3 a = std::abs(axis.x) < 0.9 ? glm::normalize(glm::cross(axis, glm::dvec3{1, 0, 0})) : glm::normalize(glm::cross(axis, glm::dvec3{0, 1, 0}));
    const glm::dvec3 b = glm::cross(axis, a);
    return glm::mat4(glm::vec4(glm::vec3(a * radius), 0), glm::vec4(glm::vec3(b * radius), 0), glm::vec4(glm::vec3(d), 0), glm::vec4(glm::vec3(p), 1));
}
} // namespace

std::string ghost_colour_name(std::size_t role) { return role_colour(role).name; }

namespace {
// The model over the kenzan as the trainee is to set it: low stems at the lean the rim allows.
Arrangement model_as_set(const LessonDef& l, const KenzanFootprint& kenzan, const components::FrameSnapshot* frame) {
    Arrangement model = model_arrangement(l, kenzan);
    if (!frame) return model;
    for (auto& s : model.stems) {
        if (const auto held = rim_held_tilt_rad(s, *frame, 0.003)) s.tilt_rad = *held;
    }
    return model;
}
double pin_tops_m(const components::FrameSnapshot* frame) { return frame && frame->kenzan ? frame->kenzan->pin_height_m() : 0.0; }
} // namespace

void add_form_ghosts(render::DrawList& list, const LessonDef& l, const KenzanFootprint& kenzan, const glm::dvec3& origin, const components::FrameSnapshot* frame) {
    if (l.scoring != "form") return;
    const Arrangement model = model_as_set(l, kenzan, frame);
    auto& rods = list.batch("cylinder", true).instances;
    auto& tips = list.batch("cube", true).instances;
    for (const auto& s : model.stems) {
        // Supporting stems too, in the colour after the main roles' (the score's to-do asks for them).
        const auto it = std::find_if(l.stems.begin(), l.stems.end(), [&](const MainStemDef& m) { return m.role == s.role; });
        if (it == l.stems.end() && s.role != "supporting") continue;
        const auto& colour = role_colour(static_cast<std::size_t>(it - l.stems.begin()));
        // A straight stem from where its line crosses the pins' tops (where the score measures it from),
        // when the frame says how tall they are.
        std::vector<glm::dvec3> line{origin + glm::dvec3(s.base_m, s.path_m.empty() ? pin_tops_m(frame) : 0.0)};
        if (s.path_m.empty()) line.push_back(line.front() + lesson_direction(s.tilt_rad, s.azimuth_rad) * s.length_m);
        for (const auto& p : s.path_m) line.push_back(origin + p);
        for (std::size_t i = 1; i < line.size(); ++i) rods.push_back({rod(line[i - 1], line[i], 0.006), glm::vec4(colour.rgb, 0.55f)});
        const glm::dvec3 tip = line.back();
        tips.push_back({glm::mat4(glm::vec4(0.018f, 0, 0, 0), glm::vec4(0, 0.018f, 0, 0), glm::vec4(0, 0, 0.018f, 0), glm::vec4(glm::vec3(tip), 1)),
                        glm::vec4(colour.rgb, 0.5f)});
    }
}

std::vector<render::OverlayPanel> form_labels(const LessonDef& l, const KenzanFootprint& kenzan, const glm::dvec3& kenzan_origin_m,
                                              const glm::dvec3& plate_origin_m, const components::FrameSnapshot* frame) {
    std::vector<render::OverlayPanel> labels;
    if (l.scoring != "form") return labels;
    const Arrangement model = model_arrangement(l, kenzan), as_set = model_as_set(l, kenzan, frame);
    for (std::size_t n = 0; n < model.stems.size(); ++n) {
        const auto& s = model.stems[n];
        const auto it = std::find_if(l.stems.begin(), l.stems.end(), [&](const MainStemDef& m) { return m.role == s.role; });
        if (it == l.stems.end()) continue;
        const glm::vec3 colour = role_colour(static_cast<std::size_t>(it - l.stems.begin())).rgb;
        // The stem's end from its place (its risen path's end when it has one): on the plate the
        // model's, over the kenzan as it is to be set there.
        const auto end_of = [](const ArrangementStem& a) {
            return a.path_m.empty() ? glm::dvec3(a.base_m, 0.0) + lesson_direction(a.tilt_rad, a.azimuth_rad) * a.length_m : a.path_m.back();
        };
        const glm::dvec3 tip = end_of(s);
        render::OverlayPanel name;
        name.scale = 1.5f;
        name.panel_colour = glm::vec4(colour * 0.6f, 0.8f);
        name.lines = {it->label.empty() ? it->role : it->label};
        name.anchor_m = glm::vec3(plate_origin_m + tip + glm::dvec3{0, 0, 0.05}); // above the marker cube
        labels.push_back(name);
        char text[96];
        const auto& set = as_set.stems[n];
        std::snprintf(text, sizeof text, "%s %.0f mm, %.0f deg", it->role.c_str(), set.length_m * 1e3, set.tilt_rad * 180.0 / 3.14159265358979323846);
        name.lines = {text};
        name.panel_colour.a = 0.6f;
        name.anchor_m = glm::vec3(kenzan_origin_m + end_of(set) + glm::dvec3{0, 0, 0.03 + (set.path_m.empty() ? pin_tops_m(frame) : 0.0)});
        labels.push_back(name);
    }
    return labels;
}

glm::dvec3 model_plate_origin(const LessonDef& l, const glm::dvec3& kenzan_origin_m) {
    const glm::dvec3 container_centre = kenzan_origin_m - glm::dvec3(l.kenzan_offset_m, 0.0);
    // Behind and right of it, as a teacher's sample stands on the table beyond the trainee's work: in
    // the view (right of the container, its right-leaning stems ran out of the picture), and clear of
    // where the trainee's stems go.
    return container_centre + glm::dvec3{0.5 * l.container.width_m, 0.5 * l.container.front_to_back_m + 0.2, 0.0};
}

void add_model_flowers(render::DrawList& list, const LessonDef& l, const KenzanFootprint& kenzan, const glm::dvec3& plate_origin_m,
                       const std::map<std::string, SpeciesDef>& species) {
    if (l.scoring != "form") return;
    components::FrameSnapshot model{};
    const Arrangement arrangement = model_arrangement(l, kenzan);
    std::vector<glm::vec3> marker_colours;
    std::vector<glm::dvec3> tips;
    for (const auto& s : arrangement.stems) {
        const auto sp = species.find(s.species);
        if (sp == species.end()) continue;
        std::vector<glm::dvec3> line{plate_origin_m + glm::dvec3(s.base_m, 0.0)};
        if (s.path_m.empty()) line.push_back(line.front() + lesson_direction(s.tilt_rad, s.azimuth_rad) * s.length_m);
        for (const auto& p : s.path_m) line.push_back(plate_origin_m + p);
        // Twenty segments along the line, as a stem's mass points are.
        double total = 0.0;
        for (std::size_t i = 1; i < line.size(); ++i) total += glm::length(line[i] - line[i - 1]);
        if (total <= 0.0) continue;
        components::FlowerStatus f{};
        f.species = s.species;
        f.diameter_m = sp->second.diameter_m;
        f.look = look_of(sp->second);
        constexpr int segments = 20;
        std::size_t at = 1;
        double walked = 0.0;
        for (int k = 0; k <= segments; ++k) {
            const double want = total * k / segments;
            while (at + 1 < line.size() && walked + glm::length(line[at] - line[at - 1]) < want) walked += glm::length(line[at] - line[at - 1]), ++at;
            const double piece = glm::length(line[at] - line[at - 1]);
            f.points_m.push_back(line[at - 1] + (line[at] - line[at - 1]) * (piece > 0.0 ? std::clamp((want - walked) / piece, 0.0, 1.0) : 0.0));
        }
        f.parts = parts_of(sp->second, static_cast<std::uint32_t>(f.points_m.size()));
        tips.push_back(f.points_m.back());
        const auto role = std::find_if(l.stems.begin(), l.stems.end(), [&](const MainStemDef& m) { return m.role == s.role; });
        marker_colours.push_back(role == l.stems.end() ? glm::vec3(0.9f) : role_colour(static_cast<std::size_t>(role - l.stems.begin())).rgb);
        model.flowers.push_back(std::move(f));
    }
    // The flowers as the world's are drawn, then a plate under them and the markers over them.
    const render::DrawList drawn = systems::build_draw_list(model);
    for (const auto& b : drawn.batches) {
        auto& into = list.batch(b.mesh, b.translucent).instances;
        into.insert(into.end(), b.instances.begin(), b.instances.end());
    }
    const auto plate = glm::vec3(kenzan.size_m.x + 0.02, kenzan.size_m.y + 0.02, kenzan.plate_thickness_m);
    list.batch("cube").instances.push_back({glm::mat4(glm::vec4(plate.x, 0, 0, 0), glm::vec4(0, plate.y, 0, 0), glm::vec4(0, 0, plate.z, 0),
                                                      glm::vec4(glm::vec3(plate_origin_m - glm::dvec3{0, 0, 0.5 * kenzan.plate_thickness_m}), 1)),
                                            {0.3f, 0.3f, 0.33f, 1.0f}});
    for (std::size_t i = 0; i < tips.size(); ++i) {
        const glm::dvec3 at = tips[i] + glm::dvec3{0, 0, 0.035};
        list.batch("cube").instances.push_back({glm::mat4(glm::vec4(0.014f, 0, 0, 0), glm::vec4(0, 0.014f, 0, 0), glm::vec4(0, 0, 0.014f, 0), glm::vec4(glm::vec3(at), 1)),
                                                glm::vec4(marker_colours[i], 1.0f)});
    }
}

} // namespace ikebana::game
