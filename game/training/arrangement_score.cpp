#include "game/training/arrangement_score.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace ikebana::game {

namespace {
constexpr double degrees = 180.0 / 3.14159265358979323846;

glm::dvec3 sample_direction(const SampleStem& s) {
    return {std::sin(s.angle_rad) * std::cos(s.azimuth_rad), std::sin(s.angle_rad) * std::sin(s.azimuth_rad), std::cos(s.angle_rad)};
}

StemComparison compare(const ArrangedStem& a, const SampleStem& s, const glm::dvec3& origin) {
    StemComparison c;
    c.species = s.species;
    const glm::dvec3 axis = a.top_m - a.base_m;
    const glm::dvec3 dir = glm::length(axis) > 0.0 ? glm::normalize(axis) : glm::dvec3{0, 0, 1};
    c.direction_error_deg = std::acos(std::clamp(glm::dot(dir, sample_direction(s)), -1.0, 1.0)) * degrees;
    c.height_error_mm = ((a.top_m.z - origin.z) - s.height_m) * 1e3;
    c.position_error_mm = glm::length(glm::dvec2(a.base_m - origin) - s.base_m) * 1e3;
    const double x = c.direction_error_deg / 10.0, y = c.height_error_mm / 20.0, z = c.position_error_mm / 8.0;
    c.score = a.fallen ? 0.0 : 100.0 * std::exp(-0.5 * (x * x + y * y + z * z));
    if (a.fallen) c.note = "fell";
    return c;
}
} // namespace

ArrangementScore score_arrangement(const std::vector<ArrangedStem>& arranged, const std::vector<SampleStem>& sample, const glm::dvec3& origin) {
    ArrangementScore out;
    std::vector<bool> used(arranged.size(), false);
    for (const auto& s : sample) {
        // The closest unused stem of the species that is in the kenzan (or fell out of it).
        std::optional<std::size_t> best;
        StemComparison best_c;
        double best_score = -1.0;
        for (std::size_t i = 0; i < arranged.size(); ++i) {
            if (used[i] || arranged[i].species != s.species || (!arranged[i].in_kenzan && !arranged[i].fallen)) continue;
            const StemComparison c = compare(arranged[i], s, origin);
            // Ties (two fallen stems) go to the nearer one.
            const double rank = c.score - 1e-6 * c.position_error_mm;
            if (rank > best_score) {
                best_score = rank;
                best = i;
                best_c = c;
            }
        }
        if (!best) {
            StemComparison missing;
            missing.species = s.species;
            missing.note = "missing";
            out.stems.push_back(missing);
            continue;
        }
        used[*best] = true;
        best_c.arranged = best;
        out.stems.push_back(best_c);
    }
    double sum = 0.0;
    for (const auto& c : out.stems) sum += c.score;
    out.score = out.stems.empty() ? 0.0 : sum / static_cast<double>(out.stems.size());
    return out;
}

std::vector<std::string> ArrangementScore::lines() const {
    std::vector<std::string> l;
    char text[200];
    std::snprintf(text, sizeof text, "RESULT: %.1f / 100 against the sample (look around with the arrows; the sample stands beside it)", score);
    l.emplace_back(text);
    for (const auto& c : stems) {
        if (c.note == "missing") {
            std::snprintf(text, sizeof text, "  %-14s missing: no %s in the kenzan", c.species.c_str(), c.species.c_str());
        } else {
            std::snprintf(text, sizeof text, "  %-14s %3.0f   direction off by %.0f deg, top %+.0f mm, place off by %.0f mm%s%s", c.species.c_str(), c.score,
                          c.direction_error_deg, c.height_error_mm, c.position_error_mm, c.note.empty() ? "" : ", ", c.note.c_str());
        }
        l.emplace_back(text);
    }
    return l;
}

} // namespace ikebana::game
