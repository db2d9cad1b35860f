#include "systems/physics/table_support_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

namespace {
bool inside_container(const Container& c, glm::dvec2 xy) { return c.holds_xy(xy); }

// Pushes a point below the rim out of the wall, to the side it is on; returns the wall's normal
// toward that side, or zero when it was not in the wall.
glm::dvec2 out_of_wall(const Container& c, glm::dvec3& x, double radius_m) {
    if (x.z >= c.rim_z_m + radius_m) return glm::dvec2{0.0};
    const glm::dvec2 d{x.x - c.centre_m.x, x.y - c.centre_m.y};
    if (c.round) {
        const double r = glm::length(d);
        const double inner = c.half_extent_m.x, outer = inner + c.wall_m;
        if (r < 1e-12 || r < inner - radius_m || r > outer + radius_m) return glm::dvec2{0.0};
        const glm::dvec2 n = d / r;
        const bool inside = r < inner + 0.5 * c.wall_m;
        const double to = inside ? inner - radius_m : outer + radius_m;
        x.x = c.centre_m.x + n.x * to;
        x.y = c.centre_m.y + n.y * to;
        return inside ? -n : n;
    }
    // A box: the nearest wall of the inside, or of the outside.
    const glm::dvec2 h = c.half_extent_m;
    const glm::dvec2 a = glm::abs(d);
    const bool inside = a.x < h.x + 0.5 * c.wall_m && a.y < h.y + 0.5 * c.wall_m;
    if (inside) {
        const double gap_x = h.x - radius_m - a.x, gap_y = h.y - radius_m - a.y;
        if (gap_x >= 0.0 && gap_y >= 0.0) return glm::dvec2{0.0};
        glm::dvec2 n{0.0};
        if (gap_x < 0.0) {
            x.x = c.centre_m.x + std::copysign(h.x - radius_m, d.x);
            n.x = -std::copysign(1.0, d.x);
        }
        if (gap_y < 0.0) {
            x.y = c.centre_m.y + std::copysign(h.y - radius_m, d.y);
            n.y = -std::copysign(1.0, d.y);
        }
        return n;
    }
    const glm::dvec2 o = h + glm::dvec2{c.wall_m + radius_m};
    if (a.x >= o.x || a.y >= o.y) return glm::dvec2{0.0};
    // Out through the nearer outer face.
    if (o.x - a.x < o.y - a.y) {
        x.x = c.centre_m.x + std::copysign(o.x, d.x);
        return {std::copysign(1.0, d.x), 0.0};
    }
    x.y = c.centre_m.y + std::copysign(o.y, d.y);
    return {0.0, std::copysign(1.0, d.y)};
}
} // namespace

void rim_supports(const Container& c, const std::vector<glm::dvec3>& x, double radius_m, std::vector<physics::SegmentSupport>& out) {
    out.clear();
    if (!c.round || x.size() < 2) return;
    const double mid = c.half_extent_m.x + 0.5 * c.wall_m;
    const double top = c.rim_z_m + radius_m;
    for (std::size_t i = 1; i < x.size(); ++i) {
        // A radius of slack above the top: a segment resting there is on the rim, not in the wall.
        if (x[i - 1].z >= top + radius_m && x[i].z >= top + radius_m) continue;
        const double ra = glm::length(glm::dvec2{x[i - 1].x, x[i - 1].y} - c.centre_m);
        const double rb = glm::length(glm::dvec2{x[i].x, x[i].y} - c.centre_m);
        if ((ra - mid) * (rb - mid) >= 0.0) continue; // both ends on one side of the wall
        const double t = (mid - ra) / (rb - ra);
        const double crossing_z = x[i - 1].z + t * (x[i].z - x[i - 1].z);
        // Well above the rim it does not touch; below the container's foot it is not in the wall.
        if (crossing_z >= top + radius_m || crossing_z < c.base_z_m) continue;
        out.push_back({static_cast<std::uint32_t>(i - 1), t, top});
    }
}

glm::dvec3 wall_push_m(const Container& container, glm::dvec3 x, double radius_m) {
    const glm::dvec3 was = x;
    (void)out_of_wall(container, x, radius_m);
    return x - was;
}

double support_floor_m(const Table* table, const Container* container, const Kenzan* kenzan, glm::dvec2 xy, double radius_m,
                       std::optional<double> end_drop_m) {
    double floor = table ? table->height_m + radius_m : -std::numeric_limits<double>::infinity();
    if (container && inside_container(*container, xy)) floor = std::max(floor, container->floor_z_m + radius_m);
    if (kenzan) {
        // The plate reaches half a pitch beyond the outer pins. The stem's bottom end stands on it by
        // its end face's lowest edge; any other point rests on it with its side.
        const glm::dvec2 half{0.5 * (kenzan->columns + 1) * kenzan->pitch_m, 0.5 * (kenzan->rows + 1) * kenzan->pitch_m};
        const glm::dvec2 d = glm::abs(xy - glm::dvec2(kenzan->origin_m));
        if (d.x < half.x && d.y < half.y) floor = std::max(floor, kenzan->origin_m.z + end_drop_m.value_or(radius_m));
    }
    return floor;
}

void TableSupportSystem::operator()(sched::SystemContext& ctx) {
    auto& reg = ctx.registry;
    const auto* table = reg.resource<const Table>();
    const auto* container = reg.single<const Container>();
    const auto* kenzan = reg.single<const Kenzan>();
    if (!table && !container && !kenzan) return;
    const auto* settings = reg.resource<const PhysicsSettings>();
    const double g = settings ? std::abs(settings->gravity_m_s2.z) : 9.80665;
    const double friction = table ? table->friction : 0.6;
    // Nothing reaches higher than this (plus a stem's radius): not the table, the container's floor or
    // rim, or the kenzan's plate. Most of a standing flower's points are far above it and are passed
    // over with one comparison (this pass was 5 % of the ten-flower tick).
    double highest = -std::numeric_limits<double>::infinity();
    if (table) highest = std::max(highest, table->height_m);
    if (container) highest = std::max({highest, container->floor_z_m, container->rim_z_m});
    if (kenzan) highest = std::max(highest, kenzan->origin_m.z);
    reg.view<StemPoints, const StemRestShape>().each([&](ecs::Entity e, StemPoints& points, const StemRestShape& rest) {
        const double radius = 0.5 * rest.diameter_m;
        const auto* clamp = reg.try_get<const StemClamp>(e);
        const bool in_tree = reg.all_of<StemFork>(e) || reg.all_of<Twigs>(e);
        // A stem that crosses the wall below the rim lies on the rim (the physics step holds it up there):
        // the points either side are not pushed apart sideways, one in and one out, which stretched the
        // segment between them across the wall.
        on_rim_.assign(points.position_m.size(), 0);
        if (container && !in_tree) {
            rim_supports(*container, points.position_m, radius, supports_);
            for (const auto& support : supports_) on_rim_[support.segment] = on_rim_[support.segment + 1] = 1;
        }
        for (std::size_t i = 0; i < points.position_m.size(); ++i) {
            if (points.position_m[i].z >= highest + radius) continue;
            if (points.pinned[i] != 0 || (i == 0 && clamp && clamp->engaged)) continue;
            auto& x = points.position_m[i];
            auto& v = points.velocity_m_s[i];
            if (!std::isfinite(x.x + x.y + x.z)) continue; // the physics' own guard deals with it
            const bool resting_on_rim = i < on_rim_.size() && on_rim_[i] != 0;
            if (container && !in_tree && !resting_on_rim) { // a tree's walls are in its solve too
                const glm::dvec2 n = out_of_wall(*container, x, radius);
                const double into = v.x * n.x + v.y * n.y;
                if (into < 0.0) {
                    v.x -= into * n.x;
                    v.y -= into * n.y;
                }
            }
            std::optional<double> end_drop;
            if (i == 0 && points.position_m.size() >= 2) {
                const glm::dvec3 axis = points.position_m[1] - x;
                const double length = glm::length(axis);
                end_drop = length > 0.0 ? radius * std::sqrt(std::max(0.0, 1.0 - axis.z * axis.z / (length * length))) : radius;
            }
            if (in_tree) continue; // its floor is in its solve (stem_tree.hpp: TreeSupport)
            const double floor = support_floor_m(table, container, kenzan, {x.x, x.y}, radius, end_drop);
            if (x.z >= floor) continue;
            x.z = floor;
            if (v.z < 0.0) v.z = 0.0;
            // Friction removes at most mu * g * dt of sliding speed per tick.
            const glm::dvec2 slide{v.x, v.y};
            const double speed = glm::length(slide);
            const double loss = friction * g * ctx.dt_s;
            const glm::dvec2 kept = speed > loss ? slide * (1.0 - loss / speed) : glm::dvec2{0.0};
            v.x = kept.x;
            v.y = kept.y;
        }
    });
}

} // namespace ikebana::systems
