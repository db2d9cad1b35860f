#pragma once
// The pin-holder: pins on a regular grid (the paper: pitch about 4.0 mm), each a cylindrical trunk
// ending in a cone tip (Figure 10). The grid is the broad phase: the pins under a point are found by
// dividing by the pitch. Passive for collision.
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

    [[nodiscard]] glm::dvec3 pin_base(std::int32_t column, std::int32_t row) const noexcept {
        return origin_m + glm::dvec3{(column - (columns - 1) * 0.5) * pitch_m, (row - (rows - 1) * 0.5) * pitch_m, 0.0};
    }
    [[nodiscard]] double pin_height_m() const noexcept { return pin.trunk_length_m + pin.tip_length_m; }
};

} // namespace ikebana::components
