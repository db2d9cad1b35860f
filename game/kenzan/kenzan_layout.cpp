#include "game/kenzan/kenzan_layout.hpp"

#include <algorithm>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/asset_paths.hpp"

namespace ikebana::game {

Result<components::Kenzan> parse_kenzan(std::string_view text, const std::string& label) {
    assets::JsonChecker c(label);
    const auto root = c.parse_object(text);
    if (!root) return c.error();
    c.no_unknown_keys(*root, "", {"format", "id", "name", "shape", "pitch_mm", "columns", "rows", "pin", "base_thickness_mm", "notes"});
    const auto format = c.string(*root, "", "format");
    if (format && *format != "ikebana-kenzan/1") c.problem("/format", "expected \"ikebana-kenzan/1\", got \"" + *format + "\"");
    components::Kenzan k{};
    k.layout = c.string(*root, "", "id").value_or("");
    k.pitch_m = c.number(*root, "", "pitch_mm", {0.5, 50}).value_or(0) * 1e-3;
    k.columns = static_cast<std::int32_t>(c.integer(*root, "", "columns", 1, 1000).value_or(0));
    k.rows = static_cast<std::int32_t>(c.integer(*root, "", "rows", 1, 1000).value_or(0));
    k.base_thickness_m = c.number(*root, "", "base_thickness_mm", {0, 100}).value_or(0) * 1e-3;
    // Round: the pins of the grid within the circle its narrower side spans (a quarter pitch of slack,
    // so that the pins on the axes at the edge are in).
    if (c.choice(*root, "", "shape", {"rectangular", "round"}, false).value_or("rectangular") == "round") {
        k.round_radius_m = (0.5 * (std::min(k.columns, k.rows) - 1) + 0.25) * k.pitch_m;
    }
    if (const auto* pin = c.object(*root, "", "pin")) {
        c.no_unknown_keys(*pin, "/pin", {"trunk_diameter_mm", "trunk_length_mm", "tip_length_mm"});
        k.pin.trunk_diameter_m = c.number(*pin, "/pin", "trunk_diameter_mm", {0.05, 10}).value_or(0) * 1e-3;
        k.pin.trunk_length_m = c.number(*pin, "/pin", "trunk_length_mm", {0.5, 100}).value_or(0) * 1e-3;
        k.pin.tip_length_m = c.number(*pin, "/pin", "tip_length_mm", {0.05, 20}).value_or(0) * 1e-3;
        if (k.pitch_m > 0 && k.pin.trunk_diameter_m >= k.pitch_m) {
            c.problem("/pin/trunk_diameter_mm", "pins would touch: must be smaller than /pitch_mm");
        }
    }
    if (!c.ok()) return c.error();
    return k;
}

Result<components::Kenzan> load_kenzan(const std::string& id_or_path) {
    const std::filesystem::path path = id_or_path.find('/') != std::string::npos || id_or_path.ends_with(".json")
                                           ? std::filesystem::path(id_or_path)
                                           : asset_dir() / "kenzan" / (id_or_path + ".json");
    auto text = assets::read_text_file(path);
    if (!text) return std::move(text).error();
    return parse_kenzan(*text, path.filename().string());
}

} // namespace ikebana::game
