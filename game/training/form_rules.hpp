#pragma once
// A form's rules checked on an arrangement (an odd number of main stems, no crossing seen from the
// front, the kenzan hidden or off centre, the stems one line at the water, the supporting stems),
// each with its points and one tip. Internal to game/training/.
#include <vector>

#include "game/training/form_score.hpp"

namespace ikebana::game::training {

RuleResult check_rule(const LessonDef& l, const RuleDef& rule, const Arrangement& a, const std::vector<const ArrangementStem*>& by_role,
                      const KenzanFootprint& k);

} // namespace ikebana::game::training
