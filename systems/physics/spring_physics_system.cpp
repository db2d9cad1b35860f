#include "systems/physics/spring_physics_system.hpp"

#include <algorithm>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

void SpringPhysicsSystem::operator()(sched::SystemContext& ctx) {
    auto& registry = ctx.registry;
    const auto* settings = registry.resource<const components::PhysicsSettings>();
    const glm::dvec3 gravity = settings ? settings->gravity_m_s2 : components::PhysicsSettings{}.gravity_m_s2;
    stems_.clear();
    registry.view<components::StemPoints, const components::StemRestShape, const components::StemSprings, components::StemLoads>().each(
        [&](ecs::Entity e, components::StemPoints& points, const components::StemRestShape& rest,
            const components::StemSprings& springs, components::StemLoads& loads) {
            const auto* clamp = registry.try_get<const components::StemClamp>(e);
            // A stiff stem's tick in equal parts (see stable_substeps); the others' external forces act
            // through all of them. The last part's end forces are what a hand feels.
            const std::size_t parts = physics::stable_substeps(points, rest, springs, clamp, ctx.dt_s);
            const bool held = std::any_of(points.pinned.begin(), points.pinned.end(), [](std::uint8_t p) { return p != 0; });
            stems_.push_back({&points, &rest, &springs, clamp, &loads, parts, held, true});
        });
    if (scratches_.size() < stems_.size()) scratches_.resize(stems_.size());
    // Stems cut into as many parts step together, their solves four at a time (step_stems); each
    // stem's results are what stepping it alone gives.
    order_.resize(stems_.size());
    for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = i;
    // Longest first within each run: a group of four costs its longest stem's rows, so similar lengths
    // share a group, and the one left alone (solved without lanes) is a short one.
    std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
        if (stems_[a].parts != stems_[b].parts) return stems_[a].parts < stems_[b].parts;
        return stems_[a].points->position_m.size() > stems_[b].points->position_m.size();
    });
    for (std::size_t first = 0, run = 0; first < order_.size(); ++run) {
        const std::size_t parts = stems_[order_[first]].parts;
        if (lane_scratch_.size() <= run) lane_scratch_.resize(run + 1);
        std::size_t last = first;
        while (last < order_.size() && stems_[order_[last]].parts == parts) ++last;
        for (std::size_t part = 0; part < parts; ++part) {
            batch_.clear();
            batch_stem_.clear();
            for (std::size_t k = first; k < last; ++k) {
                auto& stem = stems_[order_[k]];
                if (!stem.finite) continue;
                auto& scratch = scratches_[order_[k]];
                scratch.want_end_force = stem.held && part + 1 == parts; // only a held stem's last part is felt
                batch_.push_back({stem.points, stem.rest, stem.springs, stem.clamp, &scratch});
                batch_stem_.push_back(order_[k]);
            }
            batch_ok_.assign(batch_.size(), 0);
            physics::step_stems(batch_, gravity, ctx.dt_s / static_cast<double>(parts), lane_scratch_[run], batch_ok_);
            for (std::size_t j = 0; j < batch_.size(); ++j) stems_[batch_stem_[j]].finite = batch_ok_[j] != 0;
        }
        first = last;
    }
    for (std::size_t i = 0; i < stems_.size(); ++i) {
        auto& stem = stems_[i];
        auto& points = *stem.points;
        auto& loads = *stem.loads;
        const auto& end_force = scratches_[i].end_force;
        if (stem.finite) {
            // The stem's own forces of this step (springs, hinges, clamp, gravity: without what other
            // systems pushed), for whatever else needs them (a hand that holds the stem): computed once
            // a tick, here.
            loads.force_n.resize(end_force.size());
            for (std::size_t p = 0; p < end_force.size(); ++p) loads.force_n[p] = end_force[p] - points.external_force_n[p];
        } else {
            // A non-finite step is refused: the stem stays where it was, at rest, rather than
            // carrying NaN into contacts and force output.
            ++failed_steps;
            for (auto& v : points.velocity_m_s) v = glm::dvec3{0.0};
            loads.force_n.assign(points.position_m.size(), glm::dvec3{0.0});
        }
        for (auto& f : points.external_force_n) f = glm::dvec3{0.0};
    }
}

} // namespace ikebana::systems
