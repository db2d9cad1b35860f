// The form's model arrangement: the main stems at their nominal length, tilt, direction and place,
// rising as one line where the form wants it, and low supporting stems where it wants the kenzan hidden.
#include "game/training/form_score.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "game/training/form_rules.hpp"

namespace ikebana::game {

namespace {

glm::dvec2 region_centre(KenzanRegion r, glm::dvec2 size, std::size_t index) {
    const double x = 0.25 * size.x, y = 0.25 * size.y;
    switch (r) {
    case KenzanRegion::centre: return {0, 0};
    case KenzanRegion::front: return {0, -y};
    case KenzanRegion::back: return {0, y};
    case KenzanRegion::left: return {-x, 0};
    case KenzanRegion::right: return {x, 0};
    case KenzanRegion::front_left: return {-x, -y};
    case KenzanRegion::front_right: return {x, -y};
    case KenzanRegion::back_left: return {-x, y};
    case KenzanRegion::back_right: return {x, y};
    case KenzanRegion::any: break;
    }
    // Anywhere: side by side about the centre, a pin row apart.
    return {(static_cast<double>(index) - 1.0) * 0.008, 0.004};
}

// A stem that rises `rise_m` straight up, then leans so that the line from its base to its tip is
// tilted `tilt_rad`: the angle of its upper part, by bisection.
std::vector<glm::dvec3> risen_path(glm::dvec2 base, double length_m, double rise_m, double tilt_rad, double azimuth_rad) {
    const double upper = length_m - rise_m;
    const auto chord_tilt = [&](double lean) {
        const glm::dvec3 d = lesson_direction(lean, azimuth_rad) * upper;
        return std::atan2(std::hypot(d.x, d.y), rise_m + d.z);
    };
    double lo = 0.0, hi = 3.14159265358979323846 / 2.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (chord_tilt(mid) < tilt_rad ? lo : hi) = mid;
    }
    const glm::dvec3 knee(base, rise_m);
    return {knee, knee + lesson_direction(lo, azimuth_rad) * upper};
}

// Stems that rise as one line stand on neighbouring spots of a 3 x 3 block a pin row apart, placed so
// that their lines stay together longest once they part, each toward its own side at its own rate
// (`ways`: the sideways run of a stem per unit of height): of every way to put them there, the one whose
// widest gap, summed over a few heights above the base, is smallest (ties: the first found), of those
// whose lines never come closer than a pin row (a stem does not go through another). Two stems parting
// to opposite sides thus start each on the side the other leans to, a little aside, and pass beside
// each other before they part (the shoka's soe and tai: 8 mm apart at the base, 5.7 at the closest).
std::vector<glm::dvec2> one_line_bases(const std::vector<glm::dvec2>& ways) {
    constexpr double pitch_m = 0.004;
    std::vector<glm::dvec2> spots;
    for (int j = -1; j <= 1; ++j) {
        for (int i = -1; i <= 1; ++i) spots.push_back(glm::dvec2{i, j} * pitch_m);
    }
    std::vector<glm::dvec2> best, now;
    if (ways.size() > spots.size()) {
        for (std::size_t i = 0; i < ways.size(); ++i) best.push_back({(static_cast<double>(i) - 1.0) * pitch_m, 0.0});
        return best;
    }
    double best_cost = std::numeric_limits<double>::infinity();
    std::vector<bool> taken(spots.size(), false);
    // Infinite for lines that would pass through each other (closer than a pin row on their way up).
    const auto cost = [&] {
        for (std::size_t a = 0; a < now.size(); ++a) {
            for (std::size_t b = a + 1; b < now.size(); ++b) {
                for (int mm = 0; mm <= 60; ++mm) {
                    if (glm::length((now[a] + mm * 1e-3 * ways[a]) - (now[b] + mm * 1e-3 * ways[b])) < 0.9 * pitch_m) return std::numeric_limits<double>::infinity();
                }
            }
        }
        double sum = 0.0;
        for (double z : {0.0, 0.01, 0.02, 0.03}) {
            double widest = 0.0;
            for (std::size_t a = 0; a < now.size(); ++a) {
                for (std::size_t b = a + 1; b < now.size(); ++b) widest = std::max(widest, glm::length((now[a] + z * ways[a]) - (now[b] + z * ways[b])));
            }
            sum += widest;
        }
        return sum;
    };
    const std::function<void()> place = [&] {
        if (now.size() == ways.size()) {
            const double c = cost();
            if (c < best_cost - 1e-12) {
                best_cost = c;
                best = now;
            }
            return;
        }
        for (std::size_t i = 0; i < spots.size(); ++i) {
            if (taken[i]) continue;
            taken[i] = true;
            now.push_back(spots[i]);
            place();
            now.pop_back();
            taken[i] = false;
        }
    };
    place();
    if (best.empty()) { // no way at all (cannot happen with nine spots and a finite cost): the plain row
        for (std::size_t i = 0; i < ways.size(); ++i) best.push_back({(static_cast<double>(i) - 1.0) * pitch_m, 0.0});
    }
    return best;
}

const RuleDef* rule_of(const LessonDef& l, RuleKind kind) {
    for (const auto& r : l.rules) {
        if (r.kind == kind) return &r;
    }
    return nullptr;
}

// Each main stem at its nominal length, tilt and direction.
void add_main_stems(const LessonDef& l, const KenzanFootprint& k, const RuleDef* one_line, Arrangement& a) {
    for (std::size_t i = 0; i < l.stems.size(); ++i) {
        const MainStemDef& m = l.stems[i];
        ArrangementStem s;
        s.role = m.role;
        s.species = m.species.empty() ? (l.materials.empty() ? "" : l.materials.front().species) : m.species.front();
        s.length_m = nominal_length_m(l, i);
        s.tilt_rad = m.tilt_rad.target;
        s.azimuth_rad = m.azimuth_rad ? m.azimuth_rad->target : 0.0;
        // Stems that rise as one line share a point (below); the others take their region's centre.
        s.base_m = region_centre(m.region, k.size_m, i);
        if (one_line) {
            const double rise = water_level_m(l, k) + 0.5 * (one_line->min_m + one_line->max_m);
            if (rise < s.length_m) s.path_m = risen_path({0.0, 0.0}, s.length_m, rise, s.tilt_rad, s.azimuth_rad);
        }
        a.stems.push_back(std::move(s));
    }
}

// The stems that rise as one line, moved together onto their spots (one_line_bases).
void place_one_line(Arrangement& a) {
    std::vector<glm::dvec2> ways;
    for (const auto& s : a.stems) {
        const glm::dvec3 d = s.path_m.size() == 2 ? glm::normalize(s.path_m[1] - s.path_m[0]) : lesson_direction(s.tilt_rad, s.azimuth_rad);
        ways.push_back(glm::dvec2{d.x, d.y} / std::max(d.z, 0.1));
    }
    const auto bases = one_line_bases(ways);
    for (std::size_t i = 0; i < a.stems.size(); ++i) {
        auto& s = a.stems[i];
        for (auto& q : s.path_m) q += glm::dvec3(bases[i], 0.0); // its path was drawn from (0, 0)
        s.base_m = bases[i];
    }
}

// Supporting stems from the materials no main stem plays, low and leaning toward the viewer,
// across the kenzan's front from left to right until it is hidden.
void hide_kenzan(const LessonDef& l, const KenzanFootprint& k, const RuleDef& hidden, Arrangement& a) {
    std::string filler = l.materials.empty() ? "" : l.materials.back().species;
    double shortest = 1e9;
    for (const auto& s : a.stems) shortest = std::min(shortest, s.length_m);
    const std::size_t room = l.supporting.max_count;
    for (std::size_t n = 0; n < room; ++n) {
        if (training::check_rule(l, hidden, a, {}, k).ok) break;
        double x = -0.5 * k.size_m.x + 0.02 + 0.04 * static_cast<double>(n);
        if (x > 0.5 * k.size_m.x) break;
        ArrangementStem s;
        s.role = "supporting";
        s.species = filler;
        s.base_m = {x, -0.5 * k.size_m.y + 0.010};
        // Short and not too low: a flower's head bends a long low stem over.
        s.length_m = std::min(0.12, 0.35 * shortest);
        s.tilt_rad = 55.0 * 3.14159265358979323846 / 180.0;
        s.azimuth_rad = 0.0;
        // Its head inside the container's wall: in Sogetsu's upright style the kenzan sits at the front,
        // and a jushi leaning forward over the rim is pushed into the pins with its head on the rim, bent
        // over it, and tears out when let go. The room is measured along its lean from its base (where it
        // enters the pins' tops) to the wall less a margin: a round wall curves back toward the kenzan at
        // its sides (measured straight to the front, the jushi at the left end crossed it).
        if (l.container.shape != ContainerShape::vase) {
            const glm::dvec2 base = a.kenzan_offset_m.value_or(l.kenzan_offset_m) + s.base_m;
            const glm::dvec3 way = lesson_direction(s.tilt_rad, s.azimuth_rad);
            const double reach = std::hypot(way.x, way.y);
            constexpr double margin_m = 0.008, shortest_m = 0.03;
            if (reach > 1e-9) {
                const glm::dvec2 u = glm::dvec2{way.x, way.y} / reach;
                const glm::dvec2 inside{0.5 * l.container.width_m - margin_m, 0.5 * l.container.front_to_back_m - margin_m};
                const double room_m = distance_to_wall_m(l.container.shape == ContainerShape::round, inside, base, u);
                const double fits_m = room_m / reach;
                if (s.length_m > fits_m) s.length_m = std::max(shortest_m, fits_m);
            }
        }
        a.stems.push_back(std::move(s));
    }
}

} // namespace

Arrangement model_arrangement(const LessonDef& l, const KenzanFootprint& k) {
    Arrangement a;
    a.kenzan_offset_m = l.kenzan_offset_m;
    const RuleDef* one_line = rule_of(l, RuleKind::one_line_at_water);
    add_main_stems(l, k, one_line, a);
    if (one_line) place_one_line(a);
    if (const RuleDef* hidden = rule_of(l, RuleKind::kenzan_hidden_front)) hide_kenzan(l, k, *hidden, a);
    return a;
}

} // namespace ikebana::game
