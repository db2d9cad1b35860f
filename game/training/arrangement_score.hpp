#pragma once
// The training result (after the paper's Figure 2): the trainee's arrangement against the sample, stem
// by stem: how far each stem's direction, height and place in the kenzan are from the sample's, and a
// score out of 100. A stem that fell, or a sample stem with no stem of its species in the kenzan,
// scores 0.
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "game/scene/scene.hpp"

namespace ikebana::game {

struct ArrangedStem {
    std::string species;
    glm::dvec3 base_m;
    glm::dvec3 top_m;
    bool in_kenzan = false;
    bool fallen = false;
};

struct StemComparison {
    std::string species;
    std::optional<std::size_t> arranged; // which arranged stem it was matched with
    double direction_error_deg = 0.0;   // between the stem's and the sample's directions
    double height_error_mm = 0.0;       // signed: + when the stem stands higher
    double position_error_mm = 0.0;     // where it enters the kenzan
    double score = 0.0;                 // 0..100
    std::string note;                   // "fell", "missing"
};

struct ArrangementScore {
    double score = 0.0; // 0..100, the mean over the sample's stems
    std::vector<StemComparison> stems;
    [[nodiscard]] std::vector<std::string> lines() const;
};

// Tolerances: 10 degrees, 20 mm of height and 8 mm of place each cost a stem about 40 % of its score.
ArrangementScore score_arrangement(const std::vector<ArrangedStem>& arranged, const std::vector<SampleStem>& sample,
                                   const glm::dvec3& kenzan_origin_m);

} // namespace ikebana::game
