#pragma once
// Which stem plays which of a form's roles: those the arrangement names are checked, the others are
// given by the least total distance from the roles' bands. Internal to game/training/.
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include "game/training/form_score.hpp"

namespace ikebana::game::training {

// Roles given in the arrangement must be the lesson's, each once; an error names the stem's field.
Result<void> check_given_roles(const LessonDef& l, const Arrangement& a, const std::string& label);

// Roles for stems with none given: the assignment of standing stems to the remaining roles with the
// smallest total cost (dynamic programming over stems and the set of roles filled: roles are few).
void assign_roles(const LessonDef& l, Arrangement& a, const KenzanFootprint& k);

// The stem that plays each of the lesson's roles, in the lesson's order (none: no stem plays it).
std::vector<const ArrangementStem*> stems_by_role(const LessonDef& l, const Arrangement& a);

} // namespace ikebana::game::training
