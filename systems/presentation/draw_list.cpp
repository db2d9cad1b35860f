#include "systems/presentation/draw_list.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "components/hand.hpp"
#include "systems/physics/part_attachment.hpp"

namespace ikebana::systems {

using namespace components;

namespace {

// A model matrix whose x, y, z columns are the given (scaled) axes, at `origin`.
glm::mat4 frame_matrix(const glm::dvec3& x, const glm::dvec3& y, const glm::dvec3& z, const glm::dvec3& origin) {
    return glm::mat4(glm::vec4(glm::vec3(x), 0.0f), glm::vec4(glm::vec3(y), 0.0f), glm::vec4(glm::vec3(z), 0.0f), glm::vec4(glm::vec3(origin), 1.0f));
}

// Any two unit axes perpendicular to `axis` (unit).
void perpendiculars(const glm::dvec3& axis, glm::dvec3& a, glm::dvec3& b) {
    a = std::abs(axis.x) < 0.9 ? glm::normalize(glm::cross(axis, glm::dvec3{1, 0, 0})) : glm::normalize(glm::cross(axis, glm::dvec3{0, 1, 0}));
    b = glm::cross(axis, a);
}

// The unit cylinder (radius 1, z from 0 to 1) stretched from p to q.
glm::mat4 segment(const glm::dvec3& p, const glm::dvec3& q, double radius) {
    const glm::dvec3 d = q - p;
    const double length = glm::length(d);
    const glm::dvec3 axis = length > 1e-12 ? d / length : glm::dvec3{0, 0, 1};
    glm::dvec3 a, b;
    perpendiculars(axis, a, b);
    return frame_matrix(a * radius, b * radius, d, p);
}

// A container: its bottom, its wall as a ring of thin boxes (a closed cylinder would hide what is in
// it), and its water, translucent, over the kenzan.
void add_container(render::DrawList& list, const Container& c) {
    const glm::vec4 glaze{0.16f, 0.22f, 0.27f, 1.0f};
    // From where it stands to its rim (a vase filled to near its mouth is still as tall as it is).
    const double bottom_z = std::min(c.base_z_m, c.floor_z_m - c.wall_m);
    const double height = c.rim_z_m - bottom_z;
    const glm::dvec3 centre{c.centre_m, bottom_z};
    if (c.floor_z_m - c.wall_m > bottom_z + 1e-4) {
        // The fill's top (a kubari, or sand) under the water, where the kenzan stands.
        const glm::vec4 fill{0.35f, 0.3f, 0.24f, 1.0f};
        const glm::dvec3 top{c.centre_m, c.floor_z_m - c.wall_m};
        if (c.round) list.batch("cylinder").instances.push_back({frame_matrix({c.half_extent_m.x, 0, 0}, {0, c.half_extent_m.x, 0}, {0, 0, c.wall_m}, top), fill});
        else list.batch("cube").instances.push_back(
            {frame_matrix({2 * c.half_extent_m.x, 0, 0}, {0, 2 * c.half_extent_m.y, 0}, {0, 0, c.wall_m}, top + glm::dvec3{0, 0, 0.5 * c.wall_m}), fill});
    }
    auto& boxes = list.batch("cube").instances;
    if (c.round) {
        const double r = c.half_extent_m.x + 0.5 * c.wall_m;
        list.batch("cylinder").instances.push_back(
            {frame_matrix({c.half_extent_m.x, 0, 0}, {0, c.half_extent_m.x, 0}, {0, 0, c.wall_m}, centre), glaze});
        const int pieces = 48;
        const double chord = 2.0 * r * std::sin(3.14159265358979323846 / pieces) * 1.05;
        for (int i = 0; i < pieces; ++i) {
            const double a = 2.0 * 3.14159265358979323846 * (i + 0.5) / pieces;
            const glm::dvec3 radial{std::cos(a), std::sin(a), 0.0};
            const glm::dvec3 along{-std::sin(a), std::cos(a), 0.0};
            boxes.push_back({frame_matrix(radial * c.wall_m, along * chord, {0, 0, height}, centre + radial * r + glm::dvec3{0, 0, 0.5 * height}), glaze});
        }
    } else {
        const glm::dvec2 h = c.half_extent_m;
        const glm::dvec3 mid = centre + glm::dvec3{0, 0, 0.5 * height};
        boxes.push_back({frame_matrix({2 * h.x, 0, 0}, {0, 2 * h.y, 0}, {0, 0, c.wall_m}, centre + glm::dvec3{0, 0, 0.5 * c.wall_m}), glaze});
        for (const double side : {-1.0, 1.0}) {
            boxes.push_back({frame_matrix({c.wall_m, 0, 0}, {0, 2 * (h.y + c.wall_m), 0}, {0, 0, height}, mid + glm::dvec3{side * (h.x + 0.5 * c.wall_m), 0, 0}), glaze});
            boxes.push_back({frame_matrix({2 * h.x, 0, 0}, {0, c.wall_m, 0}, {0, 0, height}, mid + glm::dvec3{0, side * (h.y + 0.5 * c.wall_m), 0}), glaze});
        }
    }
    if (c.water_z_m > c.floor_z_m) {
        auto& surface = list.batch(c.round ? "cylinder" : "cube", true);
        const glm::dvec3 at{c.centre_m, c.water_z_m - 0.0005};
        surface.instances.push_back({c.round ? frame_matrix({c.half_extent_m.x, 0, 0}, {0, c.half_extent_m.x, 0}, {0, 0, 0.001}, at)
                                             : frame_matrix({2 * c.half_extent_m.x, 0, 0}, {0, 2 * c.half_extent_m.y, 0}, {0, 0, 0.001}, at),
                                     {0.45f, 0.62f, 0.75f, 0.35f}});
    }
}

// A stem's (or a twig's) petals and leaves, each placed on its point and turned with its bark.
// A leaf under the container's water (it rots there; some lessons' rules count it) is drawn in this
// colour, so that the trainee can see which leaves P is to strip (a first-timer spent six minutes
// looking).
constexpr glm::vec3 rotting_leaf_colour{0.9f, 0.35f, 0.05f};

bool under_water(const Container* c, const glm::dvec3& p) { return c && p.z < c->water_z_m && c->holds_xy(glm::dvec2(p)); }

void add_parts(render::DrawList& list, const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& directors,
               const std::vector<Part>& parts, const FlowerLook& look, const Container* container = nullptr) {
    for (const auto& part : parts) {
        const auto f = physics::attachment_frame(x, std::min<std::size_t>(part.stem_point, x.size() - 1), directors);
        // The mesh runs along +x for one unit: out along the offset's direction, as long as the part.
        const glm::dvec3 out = f.place(part.offset_m) - f.origin_m;
        const double size = 2.0 * glm::length(out);
        if (size <= 0.0) continue;
        const glm::dvec3 along = glm::normalize(out);
        const glm::dvec3 across = glm::normalize(glm::cross(f.up, along));
        const glm::dvec3 normal = glm::cross(along, across);
        glm::vec3 part_colour = (part.kind == PartKind::petal ? look.petal_colour : look.leaf_colour) * part.shade;
        if (part.kind == PartKind::leaf && under_water(container, f.origin_m)) part_colour = rotting_leaf_colour;
        // One unit long before scaling: its cup is the bend per unit.
        list.batch(part.mesh).instances.push_back(
            {frame_matrix(along * size, across * size, normal * size, f.origin_m), glm::vec4(part_colour, 1.0f), part.cup_rad});
    }
}

} // namespace

render::DrawList build_draw_list(const FrameSnapshot& frame) {
    render::DrawList list;
    if (frame.table_height_m) {
        list.batch("plane").instances.push_back(
            {frame_matrix({1.2, 0, 0}, {0, 0.8, 0}, {0, 0, 1}, {0.0, 0.0, *frame.table_height_m}), {0.62f, 0.5f, 0.36f, 1.0f}});
    }
    if (frame.container) add_container(list, *frame.container);
    if (frame.kenzan) {
        const Kenzan& k = *frame.kenzan;
        const glm::vec4 base_colour{0.18f, 0.18f, 0.2f, 1.0f};
        if (k.round_radius_m > 0.0) {
            list.batch("cylinder").instances.push_back(
                {segment(k.origin_m - glm::dvec3{0, 0, k.base_thickness_m}, k.origin_m, k.round_radius_m + 0.5 * k.pitch_m), base_colour});
        } else {
            const double w = (k.columns + 1) * k.pitch_m, d = (k.rows + 1) * k.pitch_m;
            list.batch("cube").instances.push_back(
                {frame_matrix({w, 0, 0}, {0, d, 0}, {0, 0, k.base_thickness_m}, k.origin_m - glm::dvec3{0, 0, 0.5 * k.base_thickness_m}), base_colour});
        }
        // The pins are 0.9 mm thick, about one texel of the shadow map: their shadows would only
        // shimmer, and leaving them out of the shadow pass saves a third of its time on lavapipe.
        auto& pin_batch = list.batch("cylinder_coarse");
        pin_batch.casts_shadow = false;
        auto& pins = pin_batch.instances;
        const double radius = 0.5 * k.pin.trunk_diameter_m;
        for (std::int32_t c = 0; c < k.columns; ++c) {
            for (std::int32_t row = 0; row < k.rows; ++row) {
                if (!k.has_pin(c, row)) continue;
                const glm::dvec3 base = k.pin_base(c, row);
                pins.push_back({segment(base, base + glm::dvec3{0, 0, k.pin_height_m()}, radius), {0.55f, 0.56f, 0.6f, 1.0f}});
            }
        }
        list.shadow_centre = glm::vec3(k.origin_m) + glm::vec3(0.0f, 0.0f, 0.12f);
        list.shadow_radius = 0.4f;
    }
    for (const auto& flower : frame.flowers) {
        const auto& x = flower.points_m;
        const auto& look = flower.look;
        auto& stems = list.batch("cylinder").instances;
        const glm::vec4 colour(look.stem_colour, 1.0f);
        for (std::size_t i = 0; i + 1 < x.size(); ++i) stems.push_back({segment(x[i], x[i + 1], 0.5 * flower.diameter_m), colour});
        if (!look.head_mesh.empty() && x.size() >= 2) {
            const auto f = physics::attachment_frame(x, x.size() - 1, flower.directors);
            list.batch(look.head_mesh).instances.push_back({frame_matrix(f.side, f.third, f.up, x.back()), glm::vec4(look.head_colour, 1.0f)});
        }
        if (x.empty()) continue;
        const Container* water = frame.container ? &*frame.container : nullptr;
        add_parts(list, x, flower.directors, flower.parts, look, water);
        for (const auto& twig : flower.twigs) {
            const auto& y = twig.points_m;
            for (std::size_t i = 0; i + 1 < y.size(); ++i) stems.push_back({segment(y[i], y[i + 1], 0.5 * twig.diameter_m), colour});
            if (!y.empty()) add_parts(list, y, twig.directors, twig.parts, look, water);
        }
    }
    for (const auto& cutting : frame.cuttings) {
        auto& stems = list.batch("cylinder").instances;
        const glm::vec4 colour(cutting.look.stem_colour, 1.0f);
        for (const auto& piece : cutting.pieces) {
            const auto& y = piece.points_m;
            for (std::size_t i = 0; i + 1 < y.size(); ++i) stems.push_back({segment(y[i], y[i + 1], 0.5 * piece.diameter_m), colour});
            if (!y.empty()) add_parts(list, y, piece.directors, piece.parts, cutting.look);
        }
    }
    for (std::size_t h = 0; h < 2; ++h) {
        const auto& hand = frame.hands[h];
        if (!hand.present) continue;
        const glm::vec4 colour = h == 0 ? glm::vec4(0.2f, 0.45f, 0.85f, 1.0f) : glm::vec4(0.85f, 0.3f, 0.25f, 1.0f);
        const double e = hand.edge_m;
        list.batch("cube").instances.push_back({frame_matrix({e, 0, 0}, {0, e, 0}, {0, 0, e}, hand.position_m), hand.connected ? colour : colour * 0.5f});
        // Depth on a flat screen: a thin line from the cube down to the table and a mark where it lands.
        const double floor_m = frame.table_height_m.value_or(0.0);
        const double drop = hand.position_m.z - 0.5 * e - floor_m;
        if (drop > 0.002) {
            const glm::dvec3 foot{hand.position_m.x, hand.position_m.y, floor_m + 0.0005};
            const glm::vec4 dim(glm::vec3(colour) * 0.7f, 1.0f);
            list.batch("cylinder").instances.push_back({segment(foot, hand.position_m - glm::dvec3{0, 0, 0.5 * e}, 0.0012), dim});
            list.batch("cube").instances.push_back({frame_matrix({e, 0, 0}, {0, e, 0}, {0, 0, 0.001}, foot), dim});
        }
        // Where the held stem would go in: a ring on the pin tips' plane, green or red.
        if (const auto mark = entry_mark(frame, h)) {
            const glm::vec4 ring = mark->good() ? glm::vec4(0.15f, 0.8f, 0.25f, 1.0f) : glm::vec4(0.9f, 0.1f, 0.1f, 1.0f);
            const double r = 0.006;
            for (int k = 0; k < 12; ++k) {
                const double a0 = k * 2.0 * M_PI / 12.0, a1 = (k + 1) * 2.0 * M_PI / 12.0;
                list.batch("cylinder").instances.push_back(
                    {segment(mark->at_m + glm::dvec3{r * std::cos(a0), r * std::sin(a0), 0.0}, mark->at_m + glm::dvec3{r * std::cos(a1), r * std::sin(a1), 0.0}, 0.0015), ring});
            }
            // And the way its end would go down, thin, plumb to the pin tips.
            const auto held = frame.hands[h].held_flower;
            if (held >= 0 && static_cast<std::size_t>(held) < frame.flowers.size() && !frame.flowers[static_cast<std::size_t>(held)].points_m.empty()) {
                const glm::dvec3 end = frame.flowers[static_cast<std::size_t>(held)].points_m.front();
                list.batch("cylinder").instances.push_back({segment(end, {end.x, end.y, mark->at_m.z}, 0.0008), ring * 0.8f});
            }
        }
        // What a press would take now: the whole stem, yellow, and brighter where the hand would hold it.
        if (const auto reach = stem_in_reach(frame, h)) {
            const auto& flower = frame.flowers[reach->flower];
            const auto& x = flower.points_m;
            for (std::size_t i = 0; i + 1 < x.size(); ++i) {
                const bool at_grip = i + 1 == reach->point || i == reach->point;
                list.batch("cylinder").instances.push_back(
                    {segment(x[i], x[i + 1], (at_grip ? 1.3 : 1.12) * flower.diameter_m), at_grip ? glm::vec4(1.0f, 0.6f, 0.0f, 1.0f) : glm::vec4(1.0f, 0.85f, 0.1f, 1.0f)});
            }
        }
    }
    return list;
}

std::optional<StemInReach> stem_in_reach(const FrameSnapshot& frame, std::size_t h) {
    if (h >= 2) return std::nullopt;
    const auto& hand = frame.hands[h];
    if (!hand.present || hand.holding) return std::nullopt;
    std::optional<StemInReach> best;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < frame.flowers.size(); ++f) {
        const auto& flower = frame.flowers[f];
        for (std::size_t i = 0; i < flower.points_m.size(); ++i) {
            if (!within_grab(flower.points_m[i], hand.position_m, hand.edge_m, flower.diameter_m)) continue;
            const double d = glm::length(flower.points_m[i] - hand.position_m);
            if (d < best_d) {
                best_d = d;
                best = StemInReach{f, i};
            }
        }
    }
    return best;
}

namespace {

// The ray's parameter at its closest approach to segment a-b, and the distance there; nothing when
// that point lies behind the ray's origin.
std::optional<std::pair<double, double>> ray_segment(glm::dvec3 o, glm::dvec3 d, glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 u = b - a, w = o - a;
    const double uu = glm::dot(u, u), ud = glm::dot(u, d), uw = glm::dot(u, w), dw = glm::dot(d, w);
    const double denom = uu - ud * ud; // d is unit
    double s = 0.0; // along the segment, 0..1
    if (uu > 1e-18) s = denom > 1e-12 * uu ? std::clamp((uw - ud * dw) / denom, 0.0, 1.0) : 0.0;
    // The ray's point nearest a + s u, then the segment's point nearest that (clamped both ways).
    double t = glm::dot(a + s * u - o, d);
    if (t <= 0.0) return std::nullopt;
    if (uu > 1e-18) s = std::clamp(glm::dot(o + t * d - a, u) / uu, 0.0, 1.0);
    t = std::max(glm::dot(a + s * u - o, d), 0.0);
    return std::pair{t, glm::length(o + t * d - (a + s * u))};
}

} // namespace

std::optional<RayHit> stem_under_ray(const FrameSnapshot& frame, glm::dvec3 origin_m, glm::dvec3 direction, double min_radius_m,
                                     std::optional<std::size_t> skip_flower) {
    if (glm::length(direction) < 1e-12) return std::nullopt;
    const glm::dvec3 d = glm::normalize(direction);
    std::optional<RayHit> best;
    const auto consider = [&](std::size_t f, const std::vector<glm::dvec3>& x, double diameter_m, bool twig) {
        const double r = std::max(0.5 * diameter_m, min_radius_m);
        for (std::size_t i = 0; i + 1 < x.size(); ++i) {
            const auto hit = ray_segment(origin_m, d, x[i], x[i + 1]);
            if (!hit || hit->second > r || (best && hit->first >= best->t_m)) continue;
            const glm::dvec3 at = origin_m + hit->first * d;
            best = RayHit{f, glm::length(at - x[i]) <= glm::length(at - x[i + 1]) ? i : i + 1, twig, hit->first};
        }
    };
    for (std::size_t f = 0; f < frame.flowers.size(); ++f) {
        if (skip_flower && *skip_flower == f) continue;
        const auto& flower = frame.flowers[f];
        consider(f, flower.points_m, flower.diameter_m, false);
        for (const auto& twig : flower.twigs) consider(f, twig.points_m, twig.diameter_m, true);
    }
    return best;
}

std::optional<EntryMark> entry_mark(const FrameSnapshot& frame, std::size_t h) {
    if (h >= 2 || !frame.kenzan) return std::nullopt;
    const auto& hand = frame.hands[h];
    if (!hand.holding || hand.held_flower < 0 || static_cast<std::size_t>(hand.held_flower) >= frame.flowers.size()) return std::nullopt;
    const auto& flower = frame.flowers[static_cast<std::size_t>(hand.held_flower)];
    const auto& x = flower.points_m;
    if (flower.in_kenzan || x.size() < 2) return std::nullopt;
    const glm::dvec3 end = x.front();
    // Its lower part's direction, up toward the tip (two segments: a curved stem's end segment alone
    // swung the mark about).
    const glm::dvec3 up = glm::normalize(x[std::min<std::size_t>(2, x.size() - 1)] - end);
    const auto& k = *frame.kenzan;
    const double tips_z = k.origin_m.z + k.pin_height_m();
    // The hand lowers its end (nearly) straight down, whatever its lean, and pushes it in to the
    // plate: the stem then comes out of the pins depth x tan(tilt) further along its lean, where the
    // score measures its place. (Along its line, the first mark slid 36 mm under a hikae as it went
    // down, and past 60 degrees it showed none.) Nothing below the tips, or held flatter than 80°.
    if (end.z < tips_z || up.z < std::cos(80.0 * std::numbers::pi / 180.0)) return std::nullopt;
    const glm::dvec3 bottom{end.x, end.y, k.origin_m.z};
    EntryMark mark;
    mark.at_m = bottom + up * ((tips_z - bottom.z) / up.z);
    mark.lower_tilt_rad = std::acos(std::clamp(up.z, -1.0, 1.0));
    const glm::dvec3 lo = k.pin_base(0, 0), hi = k.pin_base(k.columns - 1, k.rows - 1);
    const double edge = 0.5 * k.pitch_m;
    mark.on_pins = bottom.x >= lo.x - edge && bottom.x <= hi.x + edge && bottom.y >= lo.y - edge && bottom.y <= hi.y + edge;
    if (frame.container && mark.on_pins) {
        // Standing there at this lean, its line must stay inside the wall up to the rim (a trainee's soe
        // stood with its lower part through the suiban's wall).
        const auto& c = *frame.container;
        const glm::dvec2 from = glm::dvec2(bottom) - c.centre_m, along{up.x, up.y};
        const double rise = (c.rim_z_m - bottom.z) / up.z; // along the stem to the rim's height
        double to_wall = std::numeric_limits<double>::infinity();
        if (c.round) {
            // |from + along s| = r, the positive root.
            const double a = glm::dot(along, along), b = 2.0 * glm::dot(from, along), q = glm::dot(from, from) - c.half_extent_m.x * c.half_extent_m.x;
            if (a > 1e-12) to_wall = (-b + std::sqrt(std::max(0.0, b * b - 4.0 * a * q))) / (2.0 * a);
        } else {
            for (int i = 0; i < 2; ++i) {
                if (std::abs(along[i]) > 1e-12) to_wall = std::min(to_wall, (std::copysign(c.half_extent_m[i], along[i]) - from[i]) / along[i]);
            }
        }
        double length = 0.0;
        for (std::size_t i = 1; i < x.size(); ++i) length += glm::length(x[i] - x[i - 1]);
        mark.meets_wall = to_wall < rise && to_wall < length; // (a 59 mm jushi was told to lean less: it ends before the wall)
        // The steepest lean this way that clears the rim (the stem rests on the rim leant further).
        if (mark.meets_wall) mark.rim_tilt_rad = std::atan2(to_wall * glm::length(along), c.rim_z_m - bottom.z);
    }
    return mark;
}

} // namespace ikebana::systems
