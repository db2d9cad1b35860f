#pragma once
// Pruning: a teacher's secateurs. A hand's PruneRequest (the trainee's command at the cube) cuts off the
// twig nearest the cube at its fork, or strips the leaf or blossom nearest it, whichever is nearer
// within the cube's reach (its half edge). What comes off falls: a twig becomes a loose stem of its own
// (a Cutting, its own twigs, leaves and blossoms with it), a stripped leaf a short stem carrying it. The
// flower's Twigs list loses the twig and all its twigs.
#include <array>
#include <limits>
#include <string_view>

#include "components/appearance.hpp"
#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/ecs/hierarchy.hpp"
#include "engine/sched/system.hpp"
#include "systems/insertion/structure_reserve.hpp"

namespace ikebana::systems {

// A part's middle, as it is drawn (draw_list: from its stem point out along its offset, twice as long):
// where the cube strips it from.
[[nodiscard]] glm::dvec3 part_middle(const components::Part& part, const components::StemPoints& points, const components::StemFrame* frame);

struct PruningSystem {
    static constexpr std::string_view name = "pruning";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::HandCube, components::HandProxy, components::Flower, components::Twigs,
                                    components::StemPoints, components::StemRestShape, components::StemFrame, components::Part, ecs::Children>;
    // The pruning itself (a twig taken off its flower, a leaf put on a stalk of its own) is a structural
    // change, queued on the command buffer and applied after the system, as creating and destroying are.
    // Each twig or part's kit, reserved when the scene loaded (structure_reserve.hpp), is taken from the
    // StructureReserve.
    using writes = sched::Components<components::PruneRequest, StructureReserve>;

    void operator()(sched::SystemContext& ctx);

    // What the hands' requests found this tick (two hands; room to spare), pruned once the views end.
    struct Found {
        double distance_m = std::numeric_limits<double>::infinity();
        ecs::Entity flower = ecs::null_entity; // whose Twigs list it is on
        ecs::Entity twig = ecs::null_entity;   // a twig to cut off at its fork
        ecs::Entity part = ecs::null_entity;   // or a leaf or blossom to strip
        ecs::Entity owner = ecs::null_entity;  // the stem or twig the part grows on
    };

private:
    std::array<Found, 4> pending_{};
    std::size_t pending_count_ = 0;
};

} // namespace ikebana::systems
