#include "game/lesson/form_table.hpp"

#include <algorithm>
#include <cstdio>


namespace ikebana::game {

namespace {

std::string ratio_words(double r) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2g", r);
    return text;
}

std::string fmt(const char* f, auto... args) {
    char text[160];
    std::snprintf(text, sizeof text, f, args...);
    return text;
}

} // namespace

std::vector<FormTableRow> form_table(const LessonDef& l) {
    std::vector<FormTableRow> rows;
    for (std::size_t i = 0; i < l.stems.size(); ++i) {
        const auto& m = l.stems[i];
        FormTableRow row;
        row.stem = m.label;
        row.role = static_cast<int>(i);
        row.length = fmt("%.0f mm", nominal_length_m(l, i) * 1e3);
        // A length that follows another role's changes with the trainee's own stem: said so here, and
        // the other ratios the school teaches.
        if (m.length_of.kind == LengthBase::Kind::role) {
            std::string ratios = ratio_words(m.length_ratio.target);
            for (const double other : m.length_also) ratios += " or " + ratio_words(other);
            row.length += " (" + ratios + " x " + l.stems[m.length_of.role].label + " as cut)";
        } else if (!m.length_also.empty()) {
            for (const double other : m.length_also) row.length += fmt(" or %.0f mm", nominal_length_m(l, i) * other / m.length_ratio.target * 1e3);
        }
        row.tilt = fmt("%.0f deg +-%.0f", m.tilt_rad.target * 180.0 / 3.14159265358979323846, m.tilt_rad.tolerance * 180.0 / 3.14159265358979323846);
        row.leaning = m.azimuth_rad ? direction_words(m.azimuth_rad->target) : "any side";
        rows.push_back(std::move(row));
    }
    // The supporting stems, when a rule asks something of them.
    const auto hidden = std::find_if(l.rules.begin(), l.rules.end(), [](const RuleDef& r) { return r.kind == RuleKind::kenzan_hidden_front; });
    const bool counted = std::any_of(l.rules.begin(), l.rules.end(), [](const RuleDef& r) { return r.kind == RuleKind::supporting_count; });
    if ((hidden != l.rules.end() && hidden->supporting_only) || (counted && l.supporting.max_count > 0)) {
        FormTableRow row;
        row.supporting = true;
        row.stem = l.supporting.label;
        row.length = l.supporting.shorter_than_role ? "shorter than " + l.stems[*l.supporting.shorter_than_role].label : "any";
        if (l.supporting.max_count > 0) row.length += fmt(", up to %u", l.supporting.max_count);
        if (hidden != l.rules.end() && hidden->supporting_only) {
            row.tilt = "45 deg or more";
            row.leaning = "front, hiding 80 % of the kenzan";
        } else {
            row.tilt = "any";
            row.leaning = "any side";
        }
        rows.push_back(std::move(row));
    }
    return rows;
}

} // namespace ikebana::game
