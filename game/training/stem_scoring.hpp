#pragma once
// A main stem against its role in the form: its length, tilt, direction and place on the kenzan, each
// criterion with its target, band, measure, points and tip. Internal to game/training/.
#include <cstddef>
#include <vector>

#include "game/training/form_score.hpp"

namespace ikebana::game::training {

// The criteria of role `role`, played by `s` (none: no stem plays it), appended to out.criteria: length
// and tilt, the direction when the form gives one, the place when it names a region of the kenzan.
void score_stem(const LessonDef& l, std::size_t role, const ArrangementStem* s, const std::vector<const ArrangementStem*>& by_role,
                const KenzanFootprint& k, FormScore& out);

} // namespace ikebana::game::training
