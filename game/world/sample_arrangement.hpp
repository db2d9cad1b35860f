#pragma once
// The sample arrangement beside the trainee's (drawn as straight stems on a second kenzan base, so both
// can be looked at from any direction), and the trainee's stems as the score reads them.
#include <vector>

#include <glm/glm.hpp>

#include "components/snapshot.hpp"
#include "engine/render/draw_list.hpp"
#include "game/training/arrangement_score.hpp"

namespace ikebana::game {

class World;

// Where the sample stands: beside the kenzan, to the trainee's right.
inline constexpr glm::dvec3 sample_offset_m{0.16, 0.0, 0.0};

// The trainee's stems as the simulation last published them.
std::vector<ArrangedStem> arranged_stems(const components::FrameSnapshot& frame);
glm::dvec3 kenzan_origin(World& world);
void add_sample_to_draw_list(render::DrawList& list, World& world, const std::vector<SampleStem>& sample);

} // namespace ikebana::game
