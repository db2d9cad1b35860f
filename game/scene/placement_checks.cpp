#include "game/scene/placement_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace ikebana::game {

Result<void> check_placements(const SceneDef& scene, const components::Kenzan& kenzan, const std::map<std::string, SpeciesDef>& species) {
    const std::string file = scene.file.empty() ? std::string("scene") : scene.file.filename().string();
    const auto refuse = [&](std::size_t i, const char* field, const std::string& what) {
        return make_error(ErrorCode::invalid_argument, file + ": /flowers/" + std::to_string(i) + "/" + field + ": " + what);
    };
    char text[320];
    // The pin field, with half a pitch around it: a stem bottom beyond it meets no pin.
    const glm::dvec3 first = kenzan.pin_base(0, 0);
    const glm::dvec3 last = kenzan.pin_base(kenzan.columns - 1, kenzan.rows - 1);
    const glm::dvec2 lo = glm::dvec2(first) - 0.5 * kenzan.pitch_m;
    const glm::dvec2 hi = glm::dvec2(last) + 0.5 * kenzan.pitch_m;
    const double min_up = std::sin(min_inserted_elevation_deg * std::acos(-1.0) / 180.0);
    struct Bottom {
        std::size_t index;
        glm::dvec2 at;
        double radius;
    };
    std::vector<Bottom> bottoms;
    for (std::size_t i = 0; i < scene.flowers.size(); ++i) {
        const auto& f = scene.flowers[i];
        if (f.placement != Placement::inserted) continue;
        const auto it = species.find(f.species);
        if (it == species.end()) continue; // loading the species reports it
        const glm::dvec2 at{f.base_m};
        if (at.x < lo.x || at.x > hi.x || at.y < lo.y || at.y > hi.y) {
            std::snprintf(text, sizeof text,
                          "an inserted flower must stand on the kenzan's pins, which span x %.0f to %.0f mm and y %.0f to %.0f mm; "
                          "this one is at (%.0f, %.0f) mm (use \"placement\": \"lying\" for a flower on the table)",
                          lo.x * 1e3, hi.x * 1e3, lo.y * 1e3, hi.y * 1e3, at.x * 1e3, at.y * 1e3);
            return refuse(i, "base_mm", text);
        }
        const double reach = kenzan.round_radius_m + 0.5 * kenzan.pitch_m;
        if (kenzan.round_radius_m > 0.0 && glm::length(at - glm::dvec2(kenzan.origin_m)) > reach) {
            std::snprintf(text, sizeof text,
                          "an inserted flower must stand on the kenzan's pins, which lie within %.0f mm of its centre (a round kenzan); "
                          "this one is %.0f mm from it (use \"placement\": \"lying\" for a flower on the table)",
                          reach * 1e3, glm::length(at - glm::dvec2(kenzan.origin_m)) * 1e3);
            return refuse(i, "base_mm", text);
        }
        if (f.direction.z < min_up) {
            std::snprintf(text, sizeof text, "an inserted stem must point up out of the pins, at least %.0f degrees above the horizontal; this one points %.0f degrees %s it",
                          min_inserted_elevation_deg, std::abs(std::asin(std::clamp(f.direction.z, -1.0, 1.0))) * 180.0 / std::acos(-1.0),
                          f.direction.z < 0.0 ? "below" : "above");
            return refuse(i, "direction", text);
        }
        const double radius = 0.5 * it->second.diameter_m;
        for (const auto& other : bottoms) {
            const double apart = glm::length(at - other.at);
            if (apart < radius + other.radius) {
                std::snprintf(text, sizeof text,
                              "overlaps /flowers/%zu: their bottoms are %.1f mm apart and the stems %.1f and %.1f mm thick; two stems cannot share one place on the pins",
                              other.index, apart * 1e3, 2e3 * radius, 2e3 * other.radius);
                return refuse(i, "base_mm", text);
            }
        }
        bottoms.push_back({i, at, radius});
    }
    return {};
}

} // namespace ikebana::game
