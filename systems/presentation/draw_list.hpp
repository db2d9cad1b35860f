#pragma once
// The world as the renderer's draw list, from the published snapshot (never the simulation's
// registry): the table, the kenzan's base and its pins (one instanced cylinder), each stem from its
// mass points (a cylinder per segment), petals, leaves and heads placed on their stem points, and the
// two hand cubes.
// A hand that holds nothing shows the whole stem a press would take, in yellow; a hand that holds a
// stem shows where it would come out of the pins if lowered straight down (a ring on the pin tips'
// plane: green on the pins, red where it would miss them or lean into the container's wall).
#include <cstddef>
#include <optional>

#include "components/snapshot.hpp"
#include "engine/render/draw_list.hpp"

namespace ikebana::systems {

[[nodiscard]] render::DrawList build_draw_list(const components::FrameSnapshot& frame);

// What a press of this hand would take now: the stem point nearest its cube within the grab's reach
// (the grab's own rule). Nothing while it holds a stem, or when none is in reach.
struct StemInReach {
    std::size_t flower = 0;
    std::size_t point = 0;
};
[[nodiscard]] std::optional<StemInReach> stem_in_reach(const components::FrameSnapshot& frame, std::size_t hand);

// What the cursor points at: the nearest stem or twig segment as drawn that a ray (world space,
// `direction` unit) passes within its radius of (at least `min_radius_m`: a 3 mm willow is hard to hit
// pixel-exact), before anything else along it. `t_m`: how far along the ray it is met (the point of
// the ray nearest that segment's axis), so that a hand put there sits on the stem, under the cursor.
// Twigs count (P prunes what a hand is on); `twig` is then set, and `point` is the flower's stem point
// nearest the hit for a stem. Loose cuttings and the held stem (`skip_flower`) are not offered.
struct RayHit {
    std::size_t flower = 0;
    std::size_t point = 0;
    bool twig = false;
    double t_m = 0.0;
};
[[nodiscard]] std::optional<RayHit> stem_under_ray(const components::FrameSnapshot& frame, glm::dvec3 origin_m, glm::dvec3 direction,
                                                   double min_radius_m = 0.006, std::optional<std::size_t> skip_flower = std::nullopt);

// Where the stem this hand holds would come out of the pins if its end were lowered straight down and
// pushed in to the plate at its lean: on the pin tips' plane (where the score measures its place).
// Nothing without a kenzan, while its end is below the pin tips, or held flatter than 80 degrees.
struct EntryMark {
    glm::dvec3 at_m{0.0};
    bool on_pins = false;       // its end would go into the pin field
    bool meets_wall = false;    // standing so, it would cross the container's wall below the rim (a stem too short to reach the wall never does)
    double rim_tilt_rad = 0.0;  // then: the furthest from vertical its lower part may lean this way and clear the rim
    double lower_tilt_rad = 0.0; // its lower part's lean now (a curved stem's differs from its whole line's)
    [[nodiscard]] bool good() const noexcept { return on_pins && !meets_wall; }
};
[[nodiscard]] std::optional<EntryMark> entry_mark(const components::FrameSnapshot& frame, std::size_t hand);

} // namespace ikebana::systems
