#pragma once
// The pin-holder: pins on a regular grid (the paper: pitch about 4.0 mm), each a cylindrical trunk
// ending in a cone tip (Figure 10). The grid is the broad phase: the pins under a point are found by
// dividing by the pitch. Passive for collision.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

namespace ikebana::components {

struct PinShape {
    double trunk_diameter_m;
    double trunk_length_m; // from the base plate to where the cone starts
    double tip_length_m;   // the cone, from trunk top to point
};

struct Kenzan {
    std::string layout;       // assets/kenzan/<id>.json
    glm::dvec3 origin_m;      // centre of pin (0, 0) at the base plate's top surface
    double pitch_m;
    std::int32_t columns;     // along x
    std::int32_t rows;        // along y
    PinShape pin;
    double base_thickness_m;
    // > 0: a round kenzan, its pins on the grid within this distance of its centre, on a round base
    // of this radius plus half a pitch; 0: every pin of the grid, on a rectangular base.
    double round_radius_m = 0.0;

    [[nodiscard]] glm::dvec3 pin_base(std::int32_t column, std::int32_t row) const noexcept {
        return origin_m + glm::dvec3{(column - (columns - 1) * 0.5) * pitch_m, (row - (rows - 1) * 0.5) * pitch_m, 0.0};
    }
    // Whether the grid has a pin at (column, row): all do on a rectangular kenzan.
    [[nodiscard]] bool has_pin(std::int32_t column, std::int32_t row) const noexcept {
        if (round_radius_m <= 0.0) return true;
        const double x = (column - (columns - 1) * 0.5) * pitch_m, y = (row - (rows - 1) * 0.5) * pitch_m;
        return x * x + y * y <= round_radius_m * round_radius_m;
    }
    [[nodiscard]] double pin_height_m() const noexcept { return pin.trunk_length_m + pin.tip_length_m; }

    // The pins whose centres lie in [lo, hi] (x and y), as inclusive column and row ranges; empty
    // (lo > hi) when there are none, also for NaN or astronomically far bounds (clamped before any
    // cast, so the cast is defined and loops over the range end).
    struct PinRange {
        std::int32_t column_lo, column_hi, row_lo, row_hi;
    };
    [[nodiscard]] PinRange pins_within(glm::dvec2 lo, glm::dvec2 hi) const noexcept {
        const glm::dvec3 corner = pin_base(0, 0);
        const auto index = [](double v, std::int32_t count) {
            return std::isnan(v) ? -1.0 : std::clamp(v, -1.0, static_cast<double>(count));
        };
        PinRange r{};
        r.column_lo = static_cast<std::int32_t>(std::max(0.0, index(std::ceil((lo.x - corner.x) / pitch_m), columns)));
        r.column_hi = static_cast<std::int32_t>(std::min(columns - 1.0, index(std::floor((hi.x - corner.x) / pitch_m), columns)));
        r.row_lo = static_cast<std::int32_t>(std::max(0.0, index(std::ceil((lo.y - corner.y) / pitch_m), rows)));
        r.row_hi = static_cast<std::int32_t>(std::min(rows - 1.0, index(std::floor((hi.y - corner.y) / pitch_m), rows)));
        return r;
    }
};

} // namespace ikebana::components
