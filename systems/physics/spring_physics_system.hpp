#pragma once
// Integrates every spring stem one tick (Eq. 1-3) at the haptic rate, so the stem the trainee feels is
// the stem that is simulated. External forces written by other systems this tick are consumed.
#include <cstdint>
#include <string_view>
#include <vector>

#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"
#include "systems/physics/stem_dynamics.hpp"
#include "systems/physics/stem_tree.hpp"

namespace ikebana::systems {

struct SpringPhysicsSystem {
    static constexpr std::string_view name = "spring_physics";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "physics";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::StemRestShape, components::StemSprings, components::StemClamp,
                                    components::PhysicsSettings, components::StemFork, components::Twigs,
                                    components::Table, components::Container, components::Kenzan, components::BodyCapacity>;
    using writes = sched::Components<components::StemPoints, components::StemLoads, components::StemFrame>; // a twig's twist on its stem

    void operator()(sched::SystemContext& ctx);

    std::uint64_t failed_steps = 0; // steps refused for a non-finite result (should stay 0)

private:
    struct Stem {
        components::StemPoints* points;
        const components::StemRestShape* rest;
        const components::StemSprings* springs;
        const components::StemClamp* clamp;
        const components::StemFrame* frame;
        components::StemLoads* loads;
        std::size_t parts;
        bool held;
        bool finite;
    };
    // Working memory kept from tick to tick (the 1 kHz loop does not allocate): a stem's scratch is
    // the one at its place in the view.
    std::vector<Stem> stems_;
    std::vector<physics::StemSolverScratch> scratches_;
    std::vector<std::vector<physics::SegmentSupport>> supports_; // what each lies across this tick (a rim)
    std::vector<std::size_t> order_; // stems_' places, longest first
    std::vector<std::size_t> rank_;  // per place: its rank in order_
    std::vector<physics::StemStep> batch_;
    std::vector<std::size_t> batch_stem_;
    std::vector<std::uint8_t> batch_ok_;
    std::vector<physics::LaneScratch> lane_scratch_; // one per round (see operator())
    // Stems with twigs, each solved as one body with them (stem_tree.hpp): the root stems this tick,
    // each tree's chains and its working memory, by the root's place among them.
    std::vector<ecs::Entity> tree_roots_;
    std::vector<std::vector<physics::TreeChain>> trees_;
    std::vector<physics::TreeScratch> tree_scratches_;
    std::vector<ecs::Entity> scratch_members_;
    void step_trees(sched::SystemContext& ctx, glm::dvec3 gravity);
    // Every list above sized for the scene's BodyCapacity, once (a piece pruned off then allocates nothing).
    void size_for(const components::BodyCapacity& capacity, std::size_t rounds);
    const components::BodyCapacity* sized_for_ = nullptr;
};

} // namespace ikebana::systems
