#include "systems/collision/collision_detection_system.hpp"

#include <algorithm>
#include <cmath>

#include "engine/ecs/registry.hpp"
#include "systems/collision/narrow_phase.hpp"

namespace ikebana::systems {

using namespace components;

namespace {

std::int64_t cell_key(std::int64_t x, std::int64_t y, std::int64_t z) {
    // 21 bits per axis, offset so that negative cells pack too.
    constexpr std::int64_t bias = 1 << 20;
    return ((x + bias) & 0x1FFFFF) | (((y + bias) & 0x1FFFFF) << 21) | (((z + bias) & 0x1FFFFF) << 42);
}

// A grid index for any finite coordinate: clamped far beyond any workspace, so that the cast is
// defined and loops over indices always advance (a double of 1e15 does not change when 1 is added,
// which once hung the loop below).
std::int64_t grid_index(double scaled) {
    constexpr double limit = 1e12;
    return static_cast<std::int64_t>(std::clamp(scaled, -limit, limit));
}

template <typename F>
void for_each_cell(const collision::Bounds& b, double cell, F&& f) {
    const glm::dvec3 lo_d = glm::floor(b.lo / cell);
    const glm::dvec3 hi_d = glm::floor(b.hi / cell);
    for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(lo_d[axis]) || !std::isfinite(hi_d[axis])) return; // NaN or inf: nowhere on the grid
    }
    // A collider spanning very many cells (a huge box) is clamped to a window rather than looping forever.
    constexpr std::int64_t max_span = 64;
    const std::int64_t x0 = grid_index(lo_d.x), y0 = grid_index(lo_d.y), z0 = grid_index(lo_d.z);
    const std::int64_t x1 = std::min(grid_index(hi_d.x), x0 + max_span);
    const std::int64_t y1 = std::min(grid_index(hi_d.y), y0 + max_span);
    const std::int64_t z1 = std::min(grid_index(hi_d.z), z0 + max_span);
    for (std::int64_t x = x0; x <= x1; ++x) {
        for (std::int64_t y = y0; y <= y1; ++y) {
            for (std::int64_t z = z0; z <= z1; ++z) f(cell_key(x, y, z));
        }
    }
}

ecs::Entity owner_of(ecs::Registry& r, ecs::Entity e) {
    const auto* link = r.try_get<const ecs::ChildOf>(e);
    return link ? link->parent : e;
}

} // namespace

void CollisionDetectionSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    auto& pass = collision_pass::of(r);
    collision_pass::begin(r, pass);
    collision_pass::gather(pass, 0, 1);
    collision_pass::query(pass, 0, 1);
    collision_pass::query_pins(r, pass);
    collision_pass::publish(r, pass);
}

namespace collision_pass {

CollisionPass& of(ecs::Registry& r) {
    if (auto* pass = r.single<CollisionPass>()) return *pass;
    // Made on the first pass; its lists then keep their memory from pass to pass. Room for far more
    // than a lesson's hands and stem ends cover, so that a stem carried across the table (more cells,
    // more pairs) does not make them grow on the 1 kHz lane.
    auto& pass = r.emplace<CollisionPass>(r.create());
    pass.cells.reserve(4096);
    pass.pairs.reserve(16384);
    pass.found.reserve(1024);
    return pass;
}

void begin(ecs::Registry& r, CollisionPass& pass) {
    pass.found.clear();
    pass.pairs.clear();
    pass.pairs_tested = 0;
    // Every Active and Passive collider as it is now; Inactive ones never enter these views. The Active
    // ones come first (0 .. active_count - 1), and only they go into the cell index: a dozen stem ends
    // and hands against hundreds of parts, so the index is small and sorted at once, and every collider
    // then looks up the cells it covers (sorting an index of every collider's cells was most of the pass).
    pass.cells.clear();
    pass.entities.clear();
    pass.owners.clear();
    pass.active.clear();
    pass.colliders.clear();
    auto add = [&](ecs::Entity e, const Collider& c, bool is_active) {
        const auto slot = static_cast<std::uint32_t>(pass.entities.size());
        pass.entities.push_back(e);
        pass.colliders.push_back(c);
        pass.owners.push_back(owner_of(r, e));
        pass.active.push_back(is_active ? 1 : 0);
        if (is_active) for_each_cell(collision::bounds_of(c), pass.cell_size_m, [&](std::int64_t key) { pass.cells.emplace_back(key, slot); });
    };
    r.view<const Collider, const ActiveCollider>().each([&](ecs::Entity e, const Collider& c) { add(e, c, true); });
    pass.active_count = pass.entities.size();
    r.view<const Collider, const PassiveCollider>().each([&](ecs::Entity e, const Collider& c) { add(e, c, false); });
    std::sort(pass.cells.begin(), pass.cells.end());
}

void gather(CollisionPass& pass, std::size_t slice, std::size_t slices) {
    // Plain references, not a structured binding: clang (the fuzz build) does not let a lambda capture one.
    const auto& entities = pass.entities;
    const auto& colliders = pass.colliders;
    const auto& owners = pass.owners;
    const auto& active = pass.active;
    const auto& cells = pass.cells;
    const double cell_size_m = pass.cell_size_m;
    auto& pairs = pass.pairs;
    // Collider j of slice s meets the Active colliders i in its cells: the pair (i, j), for a Passive j
    // or an Active one after i (Active x Active once).
    const std::size_t from = entities.size() * slice / slices;
    const std::size_t to = entities.size() * (slice + 1) / slices;
    for (std::size_t j = from; j < to; ++j) {
        for_each_cell(collision::bounds_of(colliders[j]), cell_size_m, [&](std::int64_t key) {
            auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(key, std::uint32_t{0}));
            for (; it != cells.end() && it->first == key; ++it) {
                const std::uint32_t i = it->second;
                if (i == j || (active[j] && i > j) || owners[i] == owners[j]) continue; // one flower's parts never meet
                pairs.push_back((static_cast<std::uint64_t>(i) << 32) | j);
            }
        });
    }
}

void query(CollisionPass& pass, std::size_t slice, std::size_t slices) {
    auto& pairs = pass.pairs;
    auto& found = pass.found;
    auto& pairs_tested = pass.pairs_tested;
    const auto& entities = pass.entities;
    const auto& colliders = pass.colliders;
    const auto& owners = pass.owners;
    // The pairs in order, Active collider by Active collider and each one's partners by index: the
    // slices' contacts, one after another, are the whole pass's. The first slice sorts them (a pair met
    // in several cells once).
    if (slice == 0) {
        std::sort(pairs.begin(), pairs.end());
        pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    }
    const std::size_t from = pairs.size() * slice / slices;
    const std::size_t to = pairs.size() * (slice + 1) / slices;
    for (std::size_t k = from; k < to; ++k) {
        const auto i = static_cast<std::uint32_t>(pairs[k] >> 32);
        const auto j = static_cast<std::uint32_t>(pairs[k] & 0xFFFFFFFFu);
        if (owners[j] == owners[i]) continue;
        ++pairs_tested;
        if (const auto hit = collision::collide(colliders[i], colliders[j])) {
            found.push_back({entities[i], entities[j], hit->point_m, hit->normal, hit->depth_m, -1});
        }
    }
}

void query_pins(ecs::Registry& r, CollisionPass& pass) {
    auto& found = pass.found;
    auto& pairs_tested = pass.pairs_tested;
    const auto& entities = pass.entities;
    const auto& colliders = pass.colliders;
    const auto active_count = pass.active_count;
    // The kenzan: its grid is the broad phase. Only Active capsules (stem ends) meet the pins.
    r.view<const Kenzan>().each([&](ecs::Entity kenzan_entity, const Kenzan& k) {
        const double top = k.origin_m.z + k.pin_height_m();
        for (std::size_t i = 0; i < active_count; ++i) {
            const ecs::Entity e = entities[i];
            const Collider& c = colliders[i];
            if (c.kind != ShapeKind::capsule) continue;
            const auto b = collision::bounds_of(c);
            if (!(b.lo.z <= top && b.hi.z >= k.origin_m.z)) continue; // also NaN bounds
            const double reach = 0.5 * k.pin.trunk_diameter_m;
            const auto range = k.pins_within(glm::dvec2(b.lo) - reach, glm::dvec2(b.hi) + reach);
            for (auto row = range.row_lo; row <= range.row_hi; ++row) {
                for (auto col = range.column_lo; col <= range.column_hi; ++col) {
                    if (!k.has_pin(col, row)) continue;
                    ++pairs_tested;
                    const auto base = k.pin_base(col, row);
                    if (const auto hit = collision::collide_capsule_pin(c, base, k.pin)) {
                        const auto pin = row * k.columns + col;
                        found.push_back({e, kenzan_entity, hit->point_m, hit->normal, hit->depth_m, pin});
                    }
                }
            }
        }
    });
}

void publish(ecs::Registry& r, CollisionPass& pass) {
    auto* contacts = r.resource<Contacts>();
    if (!contacts) contacts = &r.set_resource<Contacts>();
    contacts->list.swap(pass.found); // the old list's memory becomes the next pass's
    contacts->pairs_tested = pass.pairs_tested;
}

} // namespace collision_pass

} // namespace ikebana::systems
