#include "game/analysis/cause_explanations.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <map>

namespace ikebana::game {

namespace {

struct Reading {
    const char* when_increasing;
    const char* when_decreasing;
};

// Only the standard columns of docs/measured-data.md: their meaning is part of the format.
const std::map<std::string, Reading>& readings() {
    static const std::map<std::string, Reading> r = {
        {"insertion",
         {"the stem end wears less with repeated insertion than the model's deterioration table and break hazards make it: "
          "its softening (or splitting) is overstated",
          "continued softening with repeated insertion: the tissue keeps tearing where the model's table stops changing "
          "(the paper's baseline is flat from the third insertion)"}},
        {"angle_deg",
         {"contact length through an oblique stem: at steeper angles the pins cross more tissue than the model's chord "
          "geometry gives",
          "contact length through an oblique stem: at flatter angles a pin crosses a longer chord of the stem than the "
          "model's geometry gives"}},
        {"depth_mm",
         {"contact length along the pins: deeper insertion engages more pin length, or denser tissue near the base plate, "
          "than the model counts",
          "contact length along the pins: deeper insertion adds less resistance than the model's contact length gives "
          "(the stem end is softer or splits)"}},
        {"pins",
         {"pins engaged by placement: each extra pin adds more than the model's share (pins crowd and compress the tissue "
          "between them)",
          "pins engaged by placement: each extra pin adds less than the model's share (neighbouring pins share torn tissue)"}},
        {"speed_mm_s",
         {"rate dependence: the tissue is viscous and resists a faster insertion more; the model's resistance is rate-independent",
          "rate dependence: a faster insertion cuts through with less resistance; the model's resistance is rate-independent"}},
        {"minutes_since_cut",
         {"drying since cutting: the outer tissue stiffens as it loses water",
          "drying since cutting: the stem loses turgor and resists the pins less"}},
        {"hole_reuse",
         {"re-used holes: a pin entering an existing hole meets compacted tissue",
          "re-used holes: a pin entering an existing hole meets tissue already torn, which the model treats as fresh"}},
        {"species", {"the species resists more than its species file says", "the species resists less than its species file says"}},
    };
    return r;
}

std::string percent(double relative) {
    char text[32];
    std::snprintf(text, sizeof text, "%+.1f %%", 100.0 * relative);
    return text;
}

} // namespace

std::string cause_span(const Cause& c) {
    char text[128];
    if (c.covariate == "insertion" && c.x_low == std::round(c.x_low) && c.x_high == std::round(c.x_high)) {
        auto ordinal = [](double v) {
            const auto n = static_cast<long long>(v);
            const char* suffix = (n % 100 >= 11 && n % 100 <= 13) ? "th" : n % 10 == 1 ? "st" : n % 10 == 2 ? "nd" : n % 10 == 3 ? "rd" : "th";
            return std::to_string(n) + suffix;
        };
        std::snprintf(text, sizeof text, "from the %s to the %s insertion", ordinal(c.x_low).c_str(), ordinal(c.x_high).c_str());
    } else {
        std::snprintf(text, sizeof text, "from %.4g to %.4g", c.x_low, c.x_high);
    }
    return text;
}

std::string explain_cause(const Cause& c) {
    char numbers[512];
    const std::string interval = percent(c.effect_low) + " to " + percent(c.effect_high);
    if (c.shape.form == "category") {
        std::snprintf(numbers, sizeof numbers,
                      "Rows with %s = '%s' measure %s against the simulation compared with the other levels (95 %% interval %s), "
                      "p = %.3g given the other terms.",
                      c.covariate.c_str(), c.category.c_str(), percent(c.effect_size).c_str(), interval.c_str(),
                      c.p_value);
    } else if (c.shape.form == "step") {
        std::snprintf(numbers, sizeof numbers,
                      "Above %s = %.4g the measured force is %s relative to the simulation compared with below it (95 %% interval %s), "
                      "p = %.3g given the other terms.",
                      c.covariate.c_str(), c.shape.scale, percent(c.effect_size).c_str(), interval.c_str(), c.p_value);
    } else if (c.shape.form == "peaked") {
        std::snprintf(numbers, sizeof numbers,
                      "The measured force relative to the simulation is %s at %s = %.4g and %s toward the ends of its range (%s): "
                      "%s at the farther end (95 %% interval %s), p = %.3g given the other terms.",
                      c.effect_size < 0.0 ? "highest" : "lowest", c.covariate.c_str(), c.shape.origin, c.effect_size < 0.0 ? "lower" : "higher",
                      cause_span(c).c_str(), percent(c.effect_size).c_str(), interval.c_str(), c.p_value);
    } else {
        std::snprintf(numbers, sizeof numbers,
                      "The measured force %s with %s relative to the simulation: %s %s, shaped %s (%s; 95 %% interval %s), "
                      "p = %.3g given the other terms.",
                      c.direction.c_str(), c.covariate.c_str(), percent(c.effect_size).c_str(), cause_span(c).c_str(), c.shape.form.c_str(),
                      describe_shape(c.shape).c_str(), interval.c_str(), c.p_value);
    }
    std::string text = numbers;
    const auto it = readings().find(c.covariate);
    if (c.shape.form == "peaked") {
        text += c.effect_size < 0.0 ? " An optimum: the stems resist most at mid values, which no monotone trend of the model gives."
                                    : " A worst value: the stems resist least at mid values, which no monotone trend of the model gives.";
    } else if (it != readings().end()) {
        text += " Physical reading: ";
        text += c.effect_size >= 0.0 ? it->second.when_increasing : it->second.when_decreasing;
        text += ".";
    } else {
        text += " The column is not one the simulation models; the extension carries it as a covariate of the trial (predict) or of "
                "the scene (--env or \"environment\" in the app).";
    }
    return text;
}

} // namespace ikebana::game
