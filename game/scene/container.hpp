#pragma once
// Containers (a suiban, a vase): what lessons and scenes describe, in one format ("container" in both,
// docs/lesson-format.md and docs/scene-format.md), parsed in one place.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/assets/json_checker.hpp"

namespace ikebana::game {

enum class ContainerShape : std::uint8_t { round, rectangular, vase };

struct ContainerDef {
    ContainerShape shape = ContainerShape::round;
    double width_m = 0.0;          // diameter (round, vase) or the side across the viewer (rectangular)
    double front_to_back_m = 0.0;  // rectangular; the diameter otherwise
    double depth_m = 0.0;          // inside height: a suiban's depth, a vase's height
    double water_depth_m = 0.0;
    // The size Sogetsu and Ohara measure stems by: the widest side plus the depth.
    [[nodiscard]] double size_m() const noexcept { return width_m + depth_m; }
};

// Reads a "container" object (`path` is its JSON pointer) into `box`; problems go to the checker.
// `also_known`: the keys the enclosing format adds (a scene's "centre_mm").
void parse_container(assets::JsonChecker& c, const assets::Json& object, const std::string& path, ContainerDef& box,
                     const std::vector<std::string>& also_known = {});

} // namespace ikebana::game
