#include "game/scene/container.hpp"

namespace ikebana::game {

using assets::Json;
using assets::JsonChecker;

void parse_container(JsonChecker& c, const Json& object, const std::string& p, ContainerDef& box, const std::vector<std::string>& also_known) {
    const Json* k = &object;
    const auto known = [&](std::vector<std::string> keys) {
        keys.insert(keys.end(), also_known.begin(), also_known.end());
        c.no_unknown_keys(*k, p, keys);
    };
    const auto shape = c.choice(*k, p, "shape", {"round", "rectangular", "vase"});
    const assets::NumberRange size{10, 2000};
    if (shape == "rectangular") {
        known(std::vector<std::string>{"shape", "width_mm", "front_to_back_mm", "depth_mm", "water_depth_mm"});
        box.shape = ContainerShape::rectangular;
        box.width_m = c.number(*k, p, "width_mm", size).value_or(0) * 1e-3;
        box.front_to_back_m = c.number(*k, p, "front_to_back_mm", size).value_or(0) * 1e-3;
        box.depth_m = c.number(*k, p, "depth_mm", size).value_or(0) * 1e-3;
    } else if (shape == "vase") {
        known(std::vector<std::string>{"shape", "diameter_mm", "height_mm", "water_depth_mm"});
        box.shape = ContainerShape::vase;
        box.width_m = box.front_to_back_m = c.number(*k, p, "diameter_mm", size).value_or(0) * 1e-3;
        box.depth_m = c.number(*k, p, "height_mm", size).value_or(0) * 1e-3;
    } else {
        known(std::vector<std::string>{"shape", "diameter_mm", "depth_mm", "water_depth_mm"});
        box.shape = ContainerShape::round;
        box.width_m = box.front_to_back_m = c.number(*k, p, "diameter_mm", size).value_or(0) * 1e-3;
        box.depth_m = c.number(*k, p, "depth_mm", size).value_or(0) * 1e-3;
    }
    const auto water = c.number(*k, p, "water_depth_mm", {0, 2000}, false);
    box.water_depth_m = water ? *water * 1e-3 : 0.8 * box.depth_m;
    if (water && box.depth_m > 0.0 && box.water_depth_m > box.depth_m) {
        c.problem(p + "/water_depth_mm", "the water (" + JsonChecker::describe(*water) + " mm) is deeper than the container");
    }
}

} // namespace ikebana::game
