#pragma once
// The form's numbers as the start screen's table shows them, a row a stem: the main stems, then the
// supporting stems when a rule scores them (Sogetsu's jushi hide the kenzan; a trainee who does not
// know that loses the rule's points without having been told).
#include <string>
#include <vector>

#include "game/lesson/lesson.hpp"

namespace ikebana::game {

struct FormTableRow {
    std::string stem;          // the role's label, or the supporting stems'
    std::string length;        // "368 mm", with "(0.75 x Shin as cut)" when it follows another's
    std::string tilt;          // "15 deg +-10"
    std::string leaning;       // "the left front", "any side", or what the supporting stems are for
    bool supporting = false;
    int role = -1;             // the main stem's index (its colour)
};

std::vector<FormTableRow> form_table(const LessonDef& lesson);

} // namespace ikebana::game
