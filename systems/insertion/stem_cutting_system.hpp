#pragma once
// Cuts the stem end (section 1: cutting is part of the simulator). The stem keeps its segment count
// and gets shorter: every rest length shrinks in proportion, the spring constants follow (axial E A / l,
// hinge E I / l), the removed length's mass goes, and the points are laid along the old shape from the
// new bottom; its bends stay where they were on the stem (moved_bends). The end is fresh: not broken, no insertions, no holes; the flower's lifetime count stays.
#include <string_view>
#include <vector>

#include "components/flower.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/ecs/hierarchy.hpp"
#include "engine/sched/system.hpp"
#include "systems/insertion/structure_reserve.hpp"

namespace ikebana::systems {

// The rest shape's hinge angles once `cut_m` is cut off the bottom and `keep` of the length stays (the
// same number of hinges, closer together): each bend stays where it was on the stem, as curvature.
std::vector<double> moved_bends(const components::StemRestShape& rest, double cut_m, double keep);
// The same into `moved`, with `scratch`'s working memory (a cut on the 1 kHz lane allocates nothing).
void moved_bends_into(const components::StemRestShape& rest, double cut_m, double keep, CutScratch& scratch, std::vector<double>& moved);
// Their directions about the stem (StemRestShape::hinge_bend_direction) go with them: each new hinge takes
// the direction of the old one nearest where it now sits.
void moved_bend_directions_into(const components::StemRestShape& rest, double cut_m, double keep, CutScratch& scratch, std::vector<glm::dvec2>& moved);

// A stem's twigs after a cut (its points laid anew from `before` to `after`, `cut_m` taken off its
// `length_m`): each moved to where it grows on the stem, or gone with the part cut off.
void move_twigs(ecs::Registry& registry, ecs::Entity flower, const std::vector<glm::dvec3>& before, const std::vector<glm::dvec3>& after,
                double cut_m, double length_m, CutScratch& scratch);

// The leaves and petals on a stem after a cut (`segments` segments, `cut_m` taken off its `length_m`):
// each moved to the point nearest where it grows on the stem, or gone with the part cut off. (They kept
// their point numbers once: on a stem cut to a third, its lower leaves were squeezed down with the points
// into the water.)
void move_parts(ecs::Registry& registry, ecs::Entity flower, std::size_t segments, double cut_m, double length_m, CutScratch& scratch);

struct StemCuttingSystem {
    static constexpr std::string_view name = "stem_cutting";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<ecs::Children>;
    // CutRequest: each request is consumed (removed) once carried out.
    using writes = sched::Components<components::CutRequest, components::StemPoints, components::StemRestShape, components::StemSprings,
                                     components::InsertionHistory, components::Twigs, components::StemFork, components::Part, StructureReserve>;

    void operator()(sched::SystemContext& ctx);

    // Nothing shorter than this is left (a cut that would go further is refused).
    double shortest_stem_m = 0.03;
};

} // namespace ikebana::systems
