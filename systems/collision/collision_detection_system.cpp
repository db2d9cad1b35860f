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

template <typename F>
void for_each_cell(const collision::Bounds& b, double cell, F&& f) {
    const auto lo = glm::floor(b.lo / cell);
    const auto hi = glm::floor(b.hi / cell);
    // A collider spanning very many cells (a huge box) is clamped to a window rather than looping forever.
    constexpr double max_span = 64.0;
    for (double x = lo.x; x <= std::min(hi.x, lo.x + max_span); ++x) {
        for (double y = lo.y; y <= std::min(hi.y, lo.y + max_span); ++y) {
            for (double z = lo.z; z <= std::min(hi.z, lo.z + max_span); ++z) {
                f(cell_key(static_cast<std::int64_t>(x), static_cast<std::int64_t>(y), static_cast<std::int64_t>(z)));
            }
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
    auto* contacts = r.resource<Contacts>();
    if (!contacts) contacts = &r.set_resource<Contacts>();
    contacts->list.clear();
    contacts->pairs_tested = 0;

    // Index every Active and Passive collider; Inactive ones never enter these views.
    cells.clear();
    entities.clear();
    owners.clear();
    active.clear();
    auto index = [&](ecs::Entity e, const Collider& c, bool is_active) {
        const auto slot = static_cast<std::uint32_t>(entities.size());
        entities.push_back(e);
        owners.push_back(owner_of(r, e));
        active.push_back(is_active ? 1 : 0);
        for_each_cell(collision::bounds_of(c), cell_size_m, [&](std::int64_t key) { cells.emplace_back(key, slot); });
    };
    r.view<const Collider, const ActiveCollider>().each([&](ecs::Entity e, const Collider& c) { index(e, c, true); });
    r.view<const Collider, const PassiveCollider>().each([&](ecs::Entity e, const Collider& c) { index(e, c, false); });
    std::sort(cells.begin(), cells.end());

    std::vector<std::uint32_t> candidates;
    for (std::uint32_t i = 0; i < entities.size(); ++i) {
        if (!active[i]) continue;
        const Collider& a = r.get<const Collider>(entities[i]);
        candidates.clear();
        for_each_cell(collision::bounds_of(a), cell_size_m, [&](std::int64_t key) {
            auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(key, std::uint32_t{0}));
            for (; it != cells.end() && it->first == key; ++it) candidates.push_back(it->second);
        });
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
        for (const std::uint32_t j : candidates) {
            if (j == i || owners[j] == owners[i]) continue;
            if (active[j] && j < i) continue; // Active x Active: each pair once
            ++contacts->pairs_tested;
            if (const auto hit = collision::collide(a, r.get<const Collider>(entities[j]))) {
                contacts->list.push_back({entities[i], entities[j], hit->point_m, hit->normal, hit->depth_m, -1});
            }
        }
    }

    // The kenzan: its grid is the broad phase. Only Active capsules (stem ends) meet the pins.
    r.view<const Kenzan>().each([&](ecs::Entity kenzan_entity, const Kenzan& k) {
        const double top = k.origin_m.z + k.pin_height_m();
        r.view<const Collider, const ActiveCollider>().each([&](ecs::Entity e, const Collider& c) {
            if (c.kind != ShapeKind::capsule) return;
            const auto b = collision::bounds_of(c);
            if (b.lo.z > top || b.hi.z < k.origin_m.z) return;
            const glm::dvec3 corner = k.pin_base(0, 0);
            const double reach = 0.5 * k.pin.trunk_diameter_m;
            const auto col_lo = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((b.lo.x - reach - corner.x) / k.pitch_m)));
            const auto col_hi = std::min<std::int64_t>(k.columns - 1, static_cast<std::int64_t>(std::floor((b.hi.x + reach - corner.x) / k.pitch_m)));
            const auto row_lo = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((b.lo.y - reach - corner.y) / k.pitch_m)));
            const auto row_hi = std::min<std::int64_t>(k.rows - 1, static_cast<std::int64_t>(std::floor((b.hi.y + reach - corner.y) / k.pitch_m)));
            for (auto row = row_lo; row <= row_hi; ++row) {
                for (auto col = col_lo; col <= col_hi; ++col) {
                    ++contacts->pairs_tested;
                    const auto base = k.pin_base(static_cast<std::int32_t>(col), static_cast<std::int32_t>(row));
                    if (const auto hit = collision::collide_capsule_pin(c, base, k.pin)) {
                        const auto pin = static_cast<std::int32_t>(row * k.columns + col);
                        contacts->list.push_back({e, kenzan_entity, hit->point_m, hit->normal, hit->depth_m, pin});
                    }
                }
            }
        });
    });
}

} // namespace ikebana::systems
