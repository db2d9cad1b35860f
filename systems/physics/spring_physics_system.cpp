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
            const auto* frame = registry.try_get<const components::StemFrame>(e);
            // A stiff stem's tick in equal parts (see stable_substeps); the others' external forces act
            // through all of them. The last part's end forces are what a hand feels.
            const std::size_t parts = physics::stable_substeps(points, rest, springs, clamp, ctx.dt_s);
            const bool held = std::any_of(points.pinned.begin(), points.pinned.end(), [](std::uint8_t p) { return p != 0; });
            stems_.push_back({&points, &rest, &springs, clamp, frame, &loads, parts, held, true});
        });
    if (scratches_.size() < stems_.size()) scratches_.resize(stems_.size());
    // The tick in rounds: round k steps every stem cut into more than k parts by its part, so a stiff
    // stem's first part is solved beside the others' whole tick and the lanes fill (step_stems: each
    // stem's results are what stepping it alone gives, whatever shares its register).
    order_.resize(stems_.size());
    for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = i;
    // Longest first: a group of four costs its longest stem's rows, so similar lengths share a group,
    // and one left alone (solved without lanes) is a short one.
    std::stable_sort(order_.begin(), order_.end(),
                     [&](std::size_t a, std::size_t b) { return stems_[a].points->position_m.size() > stems_[b].points->position_m.size(); });
    std::size_t rounds = 0;
    for (const auto& stem : stems_) rounds = std::max(rounds, stem.parts);
    if (lane_scratch_.size() < rounds) lane_scratch_.resize(rounds);
    for (std::size_t round = 0; round < rounds; ++round) {
        batch_.clear();
        batch_stem_.clear();
        for (const std::size_t k : order_) {
            auto& stem = stems_[k];
            if (stem.parts <= round || !stem.finite) continue;
            auto& scratch = scratches_[k];
            scratch.want_end_force = stem.held && round + 1 == stem.parts; // only a held stem's last part is felt
            batch_.push_back({stem.points, stem.rest, stem.springs, stem.clamp, &scratch, ctx.dt_s / static_cast<double>(stem.parts), stem.frame});
            batch_stem_.push_back(k);
        }
        batch_ok_.assign(batch_.size(), 0);
        physics::step_stems(batch_, gravity, lane_scratch_[round], batch_ok_);
        for (std::size_t j = 0; j < batch_.size(); ++j) stems_[batch_stem_[j]].finite = batch_ok_[j] != 0;
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
