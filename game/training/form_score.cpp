#include "game/training/form_score.hpp"

#include <algorithm>
#include <cmath>

#include "game/training/arrangement_score.hpp"
#include "game/training/form_rules.hpp"
#include "game/training/form_text.hpp"
#include "game/training/role_assignment.hpp"
#include "game/training/stem_geometry.hpp"
#include "game/training/stem_scoring.hpp"

namespace ikebana::game {

using training::fmt;

std::vector<std::string> FormScore::lines() const {
    std::vector<std::string> out;
    out.push_back(fmt("RESULT: %.1f / 100 (%s)", score, lesson.c_str()));
    // For each stem the criterion that lost most, or that it is within every band.
    std::vector<std::string> roles;
    for (const auto& c : criteria) {
        if (std::find(roles.begin(), roles.end(), c.stem) == roles.end()) roles.push_back(c.stem);
    }
    for (const auto& role : roles) {
        double earned = 0.0, possible = 0.0, worst_loss = 0.0;
        const Criterion* worst = nullptr;
        for (const auto& c : criteria) {
            if (c.stem != role) continue;
            earned += c.points;
            possible += c.max_points;
            if (c.max_points - c.points > worst_loss + 1e-9) {
                worst_loss = c.max_points - c.points;
                worst = &c;
            }
        }
        out.push_back(fmt("  %-9s %4.1f / %-4.0f %s", role.c_str(), earned, possible, worst ? worst->tip.c_str() : "within every band"));
    }
    for (const auto& r : rules) {
        out.push_back(fmt("  %-9s %s", r.ok ? "ok" : "rule", r.tip.c_str()));
    }
    return out;
}

Result<FormScore> score_form(const LessonDef& l, const Arrangement& arrangement, const KenzanFootprint& k, const std::string& label) {
    if (l.scoring != "form") return make_error(ErrorCode::invalid_argument, l.id + " is scored against its scene's sample, not a form");
    FormScore out;
    out.lesson = l.id;
    out.arrangement = arrangement;
    if (auto given = training::check_given_roles(l, out.arrangement, label); !given) return std::move(given).error();
    training::assign_roles(l, out.arrangement, k);
    const std::vector<const ArrangementStem*> by_role = training::stems_by_role(l, out.arrangement);
    for (std::size_t r = 0; r < l.stems.size(); ++r) training::score_stem(l, r, by_role[r], by_role, k, out);
    for (const auto& rule : l.rules) out.rules.push_back(training::check_rule(l, rule, out.arrangement, by_role, k));
    double earned = 0.0, possible = 0.0;
    for (const auto& c : out.criteria) {
        earned += c.points;
        possible += c.max_points;
    }
    for (const auto& r : out.rules) {
        earned += r.points;
        possible += r.max_points;
    }
    out.score = possible > 0.0 ? 100.0 * earned / possible : 0.0;
    out.how = fmt("Each main stem earns up to %.0f points for its length, %.0f for its tilt, %.0f for the way it leans and %.0f for its place on the kenzan: "
                  "all of them inside the form's band, none at three times the band, in a straight line between. Each rule met earns its points. "
                  "The score is the points earned out of those possible (%.0f), as a percentage.",
                  l.length_points, l.tilt_points, l.azimuth_points, l.region_points, possible);
    return out;
}

FormScore score_sample(const LessonDef& l, const Arrangement& arrangement, const std::vector<SampleStem>& sample) {
    FormScore out;
    out.lesson = l.id;
    out.arrangement = arrangement;
    std::vector<ArrangedStem> arranged;
    for (const auto& s : arrangement.stems) {
        const glm::dvec3 base(s.base_m, 0.0);
        arranged.push_back({s.species, base, training::tip_of(s), s.standing, !s.standing});
    }
    const ArrangementScore result = score_arrangement(arranged, sample, glm::dvec3{0.0});
    const double share = sample.empty() ? 0.0 : 100.0 / static_cast<double>(sample.size());
    for (std::size_t i = 0; i < result.stems.size(); ++i) {
        const StemComparison& c = result.stems[i];
        const std::string who = fmt("%s_%zu", c.species.c_str(), i + 1);
        Criterion m{who, "match", 0.0, 1.0, {}, c.score / 100.0 * share, share, {}};
        if (c.note == "missing") {
            m.tip = fmt("%s: missing: no %s in the kenzan", who.c_str(), c.species.c_str());
        } else {
            // The comparison's errors in units of its tolerances (10 degrees, 20 mm of height, 8 mm of place).
            m.measured = std::hypot(c.direction_error_deg / 10.0, c.height_error_mm / 20.0, c.position_error_mm / 8.0);
            m.tip = fmt("%s: direction off by %.0f°, top %+.0f mm, place off by %.0f mm%s%s", who.c_str(), c.direction_error_deg, c.height_error_mm,
                        c.position_error_mm, c.note.empty() ? "" : ", ", c.note.c_str());
        }
        if (c.arranged) out.arrangement.stems[*c.arranged].role = who;
        out.criteria.push_back(m);
    }
    for (auto& s : out.arrangement.stems) {
        if (s.role.empty()) s.role = "supporting";
    }
    out.score = result.score;
    out.how = "Free practice against the sample (the paper's Figure 2): each sample stem is matched with the closest stem of its species; it scores "
              "100 × exp(-(d² + h² + p²) / 2), d the direction error in 10°, h the top's height error in 20 mm, p the place error in 8 mm; the score is "
              "the mean over the sample's stems. \"measured\" is sqrt(d² + h² + p²).";
    return out;
}

} // namespace ikebana::game
