#pragma once
// Points something else holds are left to it: a hand's (pinned) and the bottom the kenzan's clamp
// holds where it entered (moving it here would fight the clamp: lifting the bottom tilts the first
// segment, which lifts the floor under the end's edge, which lifts the bottom... and the stem gains
// energy until it flies).
// Keeps stem points out of the rigid things they rest on: the table, the kenzan's base plate and a
// container's floor and wall. A point that ends a step inside one is put back on its surface, loses
// its velocity into it, and (on a floor) slides with Coulomb friction. A position correction after the
// implicit step, so the stiff contact costs nothing in stability. A branch with twigs (a tree) has its
// floors and walls in its own solve (stem_tree.hpp: TreeSupport): a stiff twig's tip put back alone is
// squeezed, or kicks the branch. (The pins are the insertion
// systems'; the plate under them is here: a stem pushed through the pins stops on it.)
#include <optional>
#include <string_view>
#include <vector>

#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"
#include "systems/physics/stem_dynamics.hpp"

namespace ikebana::systems {

struct TableSupportSystem {
    static constexpr std::string_view name = "table_support";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "constraints";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::Table, components::Container, components::Kenzan, components::StemRestShape,
                                    components::StemClamp, components::PhysicsSettings, components::StemFork, components::Twigs>;
    using writes = sched::Components<components::StemPoints>;

    void operator()(sched::SystemContext& ctx);

private:
    // Kept from tick to tick, not to allocate: the stem in hand's rim crossings and its points on them.
    std::vector<physics::SegmentSupport> supports_;
    std::vector<std::uint8_t> on_rim_;
};

// How far a point of a stem of `radius_m` at `x` must move to be out of the container's wall (zero if
// it is not in it): to the side it is on.
// Where a stem crosses a round container's wall below its rim (one point inside the wall's middle, the
// next outside): the segments that lie on the rim, each held up to a radius above it in the physics
// step (physics::SegmentSupport). Replaces `out`'s contents.
void rim_supports(const components::Container& container, const std::vector<glm::dvec3>& x, double radius_m,
                  std::vector<physics::SegmentSupport>& out);

glm::dvec3 wall_push_m(const components::Container& container, glm::dvec3 x, double radius_m);

// The floor under (x, y) for a point of a stem of `radius_m`: the table, or the container's floor, or
// the kenzan's plate, whichever is highest there. Exposed for tests.
// `end_drop_m`: for the stem's bottom point, how far its end face's lowest edge is below the point
// (the radius times the sine of its tilt); the point of any other part rests on its side, a radius up.
double support_floor_m(const components::Table* table, const components::Container* container, const components::Kenzan* kenzan,
                       glm::dvec2 xy, double radius_m, std::optional<double> end_drop_m);

} // namespace ikebana::systems
