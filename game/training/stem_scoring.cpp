#include "game/training/stem_scoring.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "game/training/form_text.hpp"
#include "game/training/stem_geometry.hpp"

namespace ikebana::game {

double band_points(double error, double tolerance, double max_points) {
    const double band = tolerance > 0.0 ? tolerance : 4.0;
    const double e = std::abs(error);
    if (e <= tolerance) return max_points;
    // Schools are strict: out of its band a criterion keeps a little, 30 % at the edge, and nothing
    // one band beyond (soe at 58 degrees for 45 +-10 earned 12.2 of 14 when it fell to nothing only
    // at three bands; now 2.9).
    return max_points * outside_band_share * std::clamp(1.0 - (e - tolerance) / band, 0.0, 1.0);
}

double position_points(double outside_mm, double max_points) {
    // A base a few millimetres off its part of the kenzan is a near miss, not a wrong form: from all
    // of the points at the edge to none 8 mm (two pin pitches) out.
    return max_points * std::clamp(1.0 - std::max(0.0, outside_mm) / 8.0, 0.0, 1.0);
}

namespace training {

namespace {

// What a role's length is a ratio of, and that in words.
struct LengthBasis {
    double m = 0.0;
    std::string words;
};

// The length's target: a ratio of the container, or of the stem that actually plays the role it follows.
LengthBasis length_basis(const LessonDef& l, const MainStemDef& m, const std::vector<const ArrangementStem*>& by_role) {
    double base_m = l.container.size_m();
    std::string base_words = fmt("the container's size (its width plus its depth), %.0f mm", base_m * 1e3);
    if (m.length_of.kind == LengthBase::Kind::container_height) {
        base_m = l.container.depth_m;
        base_words = fmt("the container's height, %.0f mm", base_m * 1e3);
    } else if (m.length_of.kind == LengthBase::Kind::role) {
        const std::size_t of = m.length_of.role;
        const bool measured = by_role[of] && by_role[of]->standing;
        base_m = measured ? by_role[of]->length_m : nominal_length_m(l, of);
        base_words = fmt("%s%s, %.0f mm", l.stems[of].role.c_str(), measured ? "" : " as the form wants it", base_m * 1e3);
    }
    return {base_m, base_words};
}

// A role's criteria: the form's targets and bands, before the stem is measured.
struct StemCriteria {
    Criterion length, tilt;
    std::optional<Criterion> azimuth;
    Criterion region;
};

// No stem plays the role, or its stem fell: no points, and tips that say which.
void score_absent(const std::string& who, const ArrangementStem* s, StemCriteria& c) {
    const std::string why = !s ? "no stem plays it" : "it fell";
    const std::string todo = !s ? fmt("choose a material for it and cut it to %.0f mm above the kenzan", c.length.target)
                                : "push it deeper into the pins, or lean it less";
    c.length.tip = fmt("%s: %s: %s", who.c_str(), why.c_str(), todo.c_str());
    c.tilt.tip = fmt("%s: %s", who.c_str(), why.c_str());
    c.region.tip = c.tilt.tip;
    if (c.azimuth) c.azimuth->tip = c.tilt.tip;
    if (s) {
        c.length.measured = s->length_m * 1e3;
        c.tilt.measured = s->tilt_rad / deg;
    }
}

void score_length(const std::string& who, const ArrangementStem& s, double ratio, const std::vector<double>& other_ratios, const LengthBasis& base,
                  Criterion& length) {
    const double length_target_mm = std::round(length.target), length_band_mm = std::round(length.tolerance);
    // Judged on the whole millimetres and degrees the tips show: 47.4 degrees was "47°, within 35 ±12"
    // in words and lost points in the bar.
    const double mm = std::round(s.length_m * 1e3);
    length.measured = mm;
    length.points = band_points(mm - length_target_mm, length_band_mm, length.max_points);
    const std::string band = fmt("%.0f mm ±%.0f (%.2f × %s)", length_target_mm, length_band_mm, ratio, base.words.c_str());
    const std::string want = "the form wants " + band;
    if (std::abs(mm - length_target_mm) <= length_band_mm) length.tip = fmt("%s: %.0f mm long, within %s", who.c_str(), mm, band.c_str());
    else if (mm > length_target_mm) length.tip = fmt("%s: %.0f mm long, %s, %.0f mm beyond it: cut it %.0f mm shorter", who.c_str(), mm, want.c_str(),
                                                     mm - length_target_mm - length_band_mm, mm - length_target_mm);
    else length.tip = fmt("%s: %.0f mm long, %s, %.0f mm below it: it is %.0f mm short; use a longer material, or cut less off", who.c_str(), mm, want.c_str(),
                          length_target_mm - length_band_mm - mm, length_target_mm - mm);
    // A school that teaches more than one ratio: a stem out of every band hears of the others too (it
    // was judged against the nearest; the trainee may have cut for another).
    if (std::abs(mm - length_target_mm) <= length_band_mm) return;
    for (const double other : other_ratios) {
        const double other_mm = std::round(length.target / ratio * other);
        const double off_mm = mm - other_mm;
        length.tip += fmt("; the form also takes %.0f mm (%.2f × %s): %s", other_mm, other, base.words.c_str(),
                          off_mm > 0.0 ? fmt("cut it %.0f mm shorter for that", off_mm).c_str() : fmt("for that it is %.0f mm short", -off_mm).c_str());
    }
}

void score_tilt(const std::string& who, const ArrangementStem& s, const MainStemDef& m, Criterion& tilt) {
    const double t = std::round(s.tilt_rad / deg);
    tilt.measured = t;
    // The form's numbers as the tip writes them: degrees to radians and back must not cost the edge.
    tilt.target = std::round(tilt.target * 1e6) / 1e6;
    tilt.tolerance = std::round(tilt.tolerance * 1e6) / 1e6;
    tilt.points = band_points(t - tilt.target, tilt.tolerance, tilt.max_points);
    const std::string lean = m.azimuth_rad ? " toward the " + direction_words(m.azimuth_rad->target) : "";
    if (std::abs(t - tilt.target) <= tilt.tolerance) {
        tilt.tip = fmt("%s: %.0f° from vertical, within the form's %.0f° ±%.0f°", who.c_str(), t, tilt.target, tilt.tolerance);
    } else if (t < tilt.target) {
        // How far, in degrees, to the form's angle: what a hand can do, not a coordinate.
        tilt.tip = fmt("%s: %.0f° from vertical, the form wants %.0f° ±%.0f°, %.0f° outside it: lean it %.0f° more%s", who.c_str(), t, tilt.target, tilt.tolerance,
                       tilt.target - tilt.tolerance - t, tilt.target - t, lean.c_str());
    } else {
        tilt.tip = fmt("%s: %.0f° from vertical, the form wants %.0f° ±%.0f°, %.0f° outside it: raise it %.0f° toward upright", who.c_str(), t, tilt.target,
                       tilt.tolerance, t - tilt.target - tilt.tolerance, t - tilt.target);
    }
}

// Direction: meaningless for a stem that stands straight up.
void score_azimuth(const std::string& who, const ArrangementStem& s, Criterion& azimuth) {
    const double t = s.tilt_rad / deg;
    const std::string want_dir = direction_words(azimuth.target);
    if (t < 1.0) {
        azimuth.measured.reset();
        azimuth.tip = fmt("%s: stands straight up, so it leans no way; the form leans it toward the %s (%.0f° ±%.0f°)", who.c_str(), want_dir.c_str(),
                          azimuth.target, azimuth.tolerance);
        return;
    }
    azimuth.target = std::round(azimuth.target * 1e6) / 1e6;
    azimuth.tolerance = std::round(azimuth.tolerance * 1e6) / 1e6;
    const double a = std::round(wrap_deg(s.azimuth_rad / deg));
    const double err = wrap_deg(a - azimuth.target);
    azimuth.measured = wrap_deg(a);
    azimuth.points = band_points(err, azimuth.tolerance, azimuth.max_points);
    if (std::abs(err) <= azimuth.tolerance) {
        azimuth.tip = fmt("%s: leans toward the %s (%.0f°), within the form's %.0f° ±%.0f°", who.c_str(), direction_words(s.azimuth_rad).c_str(), wrap_deg(a),
                          azimuth.target, azimuth.tolerance);
    } else {
        azimuth.tip = fmt("%s: leans toward the %s (%.0f°), the form wants the %s (%.0f° ±%.0f°), %.0f° outside it: turn it %.0f° to the %s", who.c_str(),
                          direction_words(s.azimuth_rad).c_str(), wrap_deg(a), want_dir.c_str(), azimuth.target, azimuth.tolerance,
                          std::abs(err) - azimuth.tolerance, std::abs(err),
                          err > 0 ? "right (clockwise seen from above)" : "left (anticlockwise seen from above)");
    }
}

// Place on the kenzan
void score_region(const std::string& who, const ArrangementStem& s, const MainStemDef& m, const KenzanFootprint& k, Criterion& region) {
    const double out_mm = outside_region(s.base_m, m.region, k.size_m) * 1e3;
    region.measured = out_mm;
    region.tolerance = 0.0;
    region.points = position_points(out_mm, region.max_points);
    region.tip = out_mm <= 0.0 ? fmt("%s: enters %s of the kenzan, where the form puts it", who.c_str(), where_on_kenzan(s.base_m, k.size_m).c_str())
                               : fmt("%s: enters %s of the kenzan; the form puts it in %s: move its base %.0f mm toward %s", who.c_str(),
                                     where_on_kenzan(s.base_m, k.size_m).c_str(), region_words(m.region).c_str(), out_mm, region_words(m.region).c_str());
}

} // namespace

void score_stem(const LessonDef& l, std::size_t r, const ArrangementStem* s, const std::vector<const ArrangementStem*>& by_role, const KenzanFootprint& k,
                FormScore& out) {
    const MainStemDef& m = l.stems[r];
    const std::string& who = m.role;
    const LengthBasis base = length_basis(l, m, by_role);
    // A school that teaches more than one ratio (Sogetsu's hikae: 3/4 of soe, or 1/2) is scored
    // against the one the stem is nearest.
    double ratio = m.length_ratio.target;
    for (const double other : m.length_also) {
        if (s && s->standing && std::abs(s->length_m - base.m * other) < std::abs(s->length_m - base.m * ratio)) ratio = other;
    }
    const double length_target_mm = base.m * ratio * 1e3;
    const double length_band_mm = base.m * m.length_ratio.tolerance * 1e3;
    StemCriteria c{{who, "length_mm", length_target_mm, length_band_mm, {}, 0.0, l.length_points, {}},
                   {who, "tilt_deg", m.tilt_rad.target / deg, m.tilt_rad.tolerance / deg, {}, 0.0, l.tilt_points, {}},
                   std::nullopt,
                   {who, "region_mm", 0.0, 0.0, {}, 0.0, l.region_points, {}}};
    if (m.azimuth_rad) c.azimuth = Criterion{who, "azimuth_deg", m.azimuth_rad->target / deg, m.azimuth_rad->tolerance / deg, {}, 0.0, l.azimuth_points, {}};
    const bool present = s && s->standing;
    if (!s || !present) {
        score_absent(who, s, c);
    } else {
        std::vector<double> others = m.length_also;
        if (!others.empty()) others.push_back(m.length_ratio.target);
        std::erase(others, ratio);
        score_length(who, *s, ratio, others, base, c.length);
        score_tilt(who, *s, m, c.tilt);
        if (c.azimuth) score_azimuth(who, *s, *c.azimuth);
        score_region(who, *s, m, k, c.region);
    }
    out.criteria.push_back(c.length);
    out.criteria.push_back(c.tilt);
    if (c.azimuth) out.criteria.push_back(*c.azimuth);
    if (m.region != KenzanRegion::any) out.criteria.push_back(c.region);
}

} // namespace training

} // namespace ikebana::game
