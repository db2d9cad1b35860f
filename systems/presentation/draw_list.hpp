#pragma once
// The world as the renderer's draw list, from the published snapshot (never the simulation's
// registry): the table, the kenzan's base and its pins (one instanced cylinder), each stem from its
// mass points (a cylinder per segment), petals, leaves and heads placed on their stem points, and the
// two hand cubes.
// A hand that holds nothing shows the whole stem a press would take, in yellow; a hand that holds a
// stem shows where its lower end would enter if lowered along its line (a ring on the pin tips' plane:
// green on the pins, red where it would miss them or meet the container's wall).
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

// Where the stem this hand holds would enter if lowered along its line: on the pin tips' plane. Nothing
// without a kenzan, or while its line does not go down.
struct EntryMark {
    glm::dvec3 at_m{0.0};
    bool on_pins = false;       // inside the pin field
    bool meets_wall = false;    // its way down from the stem's end crosses the container's wall
    [[nodiscard]] bool good() const noexcept { return on_pins && !meets_wall; }
};
[[nodiscard]] std::optional<EntryMark> entry_mark(const components::FrameSnapshot& frame, std::size_t hand);

} // namespace ikebana::systems
