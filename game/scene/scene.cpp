#include "game/scene/scene.hpp"

#include "engine/core/utf8.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"

namespace ikebana::game {

using assets::Json;
using assets::JsonChecker;

namespace {
std::optional<glm::dvec3> vec3(JsonChecker& c, const Json& object, const std::string& path, const char* key,
                               bool required, double scale, assets::NumberRange range = {}) {
    const auto v = c.numbers(object, path, key, range, 3, required);
    if (!v) return std::nullopt;
    if (v->size() != 3) {
        c.problem(path + "/" + key, "expected exactly 3 numbers, got " + std::to_string(v->size()));
        return std::nullopt;
    }
    return glm::dvec3{(*v)[0], (*v)[1], (*v)[2]} * scale;
}
} // namespace

Result<SceneDef> parse_scene(std::string_view text, const std::string& label) {
    JsonChecker c(label);
    const auto root = c.parse_object(text);
    if (!root) return c.error();
    c.no_unknown_keys(*root, "", {"format", "name", "seed", "rates_hz", "gravity_m_s2", "table_height_mm", "kenzan",
                                  "flowers", "hands", "environment", "force_scheme", "sample", "display", "container", "notes"});
    const auto format = c.string(*root, "", "format");
    if (format && *format != "ikebana-scene/1") c.problem("/format", "expected \"ikebana-scene/1\", got \"" + *format + "\"");
    SceneDef s{};
    const assets::NumberRange workspace{-workspace_half_extent_m * 1e3, workspace_half_extent_m * 1e3};
    s.seed = static_cast<std::uint64_t>(c.integer(*root, "", "seed", 0, std::numeric_limits<std::int64_t>::max(), false).value_or(1));
    s.gravity_m_s2 = vec3(c, *root, "", "gravity_m_s2", false, 1.0, {-max_gravity_m_s2, max_gravity_m_s2}).value_or(glm::dvec3{0, 0, -9.80665});
    s.table_height_m = c.number(*root, "", "table_height_mm", {-1000, 1000}, false).value_or(0) * 1e-3;
    if (const auto* rates = c.object(*root, "", "rates_hz", false)) {
        for (const auto& [name, value] : rates->items()) {
            if (const auto hz = c.number(*rates, "/rates_hz", name.c_str(), {0.001, 100000})) s.rates_hz[name] = *hz;
        }
    }
    s.force_scheme = c.choice(*root, "", "force_scheme", {"full_rate", "paper"}, false).value_or("full_rate");
    if (const auto* env = c.object(*root, "", "environment", false)) {
        for (const auto& [name, value] : env->items()) {
            if (value.is_number()) s.environment.numeric[name] = value.get<double>();
            else if (value.is_string()) s.environment.category[name] = value.get<std::string>();
            else c.problem("/environment/" + name, "expected a number or a string, got " + JsonChecker::describe(value));
        }
    }
    if (const auto* display = c.object(*root, "", "display", false)) {
        const std::string p = "/display";
        c.no_unknown_keys(*display, p, {"stereo", "eye_separation_mm", "screen_distance_mm", "vertical_fov_deg", "camera_mm", "target_mm"});
        s.display.camera_position_m = vec3(c, *display, p, "camera_mm", false, 1e-3, workspace);
        s.display.camera_target_m = vec3(c, *display, p, "target_mm", false, 1e-3, workspace);
        if (s.display.camera_position_m && s.display.camera_target_m &&
            glm::length(*s.display.camera_position_m - *s.display.camera_target_m) < 0.01) {
            c.problem(p + "/target_mm", "is within 10 mm of camera_mm: the camera must look somewhere");
        }
        s.display.stereo = c.choice(*display, p, "stereo", {"sbs", "rows", "anaglyph", "mono"}, false).value_or("sbs");
        s.display.eye_separation_m = c.number(*display, p, "eye_separation_mm", {0, 200}, false).value_or(65) * 1e-3;
        s.display.screen_distance_m = c.number(*display, p, "screen_distance_mm", {50, 5000}, false).value_or(460) * 1e-3;
        s.display.vertical_fov_rad = c.number(*display, p, "vertical_fov_deg", {5, 150}, false).value_or(40.1) * std::acos(-1.0) / 180.0;
    }
    if (const auto* sample = c.array(*root, "", "sample", false)) {
        for (std::size_t i = 0; i < sample->size(); ++i) {
            const std::string p = "/sample/" + std::to_string(i);
            const Json& st = (*sample)[i];
            if (!st.is_object()) {
                c.problem(p, "expected an object, got " + JsonChecker::describe(st));
                continue;
            }
            c.no_unknown_keys(st, p, {"species", "base_mm", "angle_deg", "azimuth_deg", "height_mm"});
            SampleStem stem{};
            stem.species = c.string(st, p, "species").value_or("");
            const auto base = c.numbers(st, p, "base_mm", {-500, 500}, 2);
            if (base && base->size() != 2) c.problem(p + "/base_mm", "expected [x, y]");
            else if (base) stem.base_m = glm::dvec2{(*base)[0], (*base)[1]} * 1e-3;
            stem.angle_rad = c.number(st, p, "angle_deg", {0, 90}).value_or(0) * std::acos(-1.0) / 180.0;
            stem.azimuth_rad = c.number(st, p, "azimuth_deg", {-360, 360}, false).value_or(0) * std::acos(-1.0) / 180.0;
            stem.height_m = c.number(st, p, "height_mm", {1, 2000}).value_or(100) * 1e-3;
            s.sample.push_back(stem);
        }
    }
    if (const auto* box = c.object(*root, "", "container", false)) {
        ContainerDef def;
        parse_container(c, *box, "/container", def, {"centre_mm"});
        const auto centre = c.numbers(*box, "/container", "centre_mm", {-workspace_half_extent_m * 1e3, workspace_half_extent_m * 1e3}, 2, false);
        if (centre && centre->size() != 2) c.problem("/container/centre_mm", "expected [x, y]");
        else if (centre) s.container_centre_m = glm::dvec2{(*centre)[0], (*centre)[1]} * 1e-3;
        s.container = def;
    }
    if (const auto* k = c.object(*root, "", "kenzan")) {
        c.no_unknown_keys(*k, "/kenzan", {"layout", "position_mm"});
        s.kenzan_layout = c.string(*k, "/kenzan", "layout").value_or("");
        s.kenzan_position_m = vec3(c, *k, "/kenzan", "position_mm", false, 1e-3, workspace).value_or(glm::dvec3{0.0});
    }
    if (const auto* flowers = c.array(*root, "", "flowers", false)) {
        if (flowers->size() > max_scene_flowers) {
            c.problem("/flowers", std::to_string(flowers->size()) + " flowers, more than the " + std::to_string(max_scene_flowers) + " a scene may have");
        }
        for (std::size_t i = 0; i < flowers->size() && i < max_scene_flowers; ++i) {
            const std::string p = "/flowers/" + std::to_string(i);
            const Json& f = (*flowers)[i];
            if (!f.is_object()) {
                c.problem(p, "expected an object, got " + JsonChecker::describe(f));
                continue;
            }
            c.no_unknown_keys(f, p, {"species", "placement", "base_mm", "direction", "inserted_depth_mm", "length_mm"});
            FlowerPlacement fp{};
            fp.species = c.string(f, p, "species").value_or("");
            fp.placement = c.choice(f, p, "placement", {"inserted", "lying"}) == "lying" ? Placement::lying : Placement::inserted;
            fp.base_m = vec3(c, f, p, "base_mm", true, 1e-3, workspace).value_or(glm::dvec3{0.0});
            fp.direction = vec3(c, f, p, "direction", true, 1.0).value_or(glm::dvec3{0, 0, 1});
            // Only its direction counts: scaled by its largest component first, as [1e200, 1e200, 1e200]
            // (whose length overflows) points where [1, 1, 1] does.
            const double largest = std::max({std::abs(fp.direction.x), std::abs(fp.direction.y), std::abs(fp.direction.z)});
            if (!(largest > 0.0) || !std::isfinite(largest) || glm::length(fp.direction / largest) < 1e-9) {
                c.problem(p + "/direction", "must not be the zero vector");
            } else {
                fp.direction = glm::normalize(fp.direction / largest);
            }
            fp.inserted_depth_m = c.number(f, p, "inserted_depth_mm", {0, 100}, false).value_or(10) * 1e-3;
            fp.length_m = c.number(f, p, "length_mm", {20, 3000}, false).value_or(0) * 1e-3;
            s.flowers.push_back(fp);
        }
    }
    if (const auto* hands = c.array(*root, "", "hands", false)) {
        for (std::size_t i = 0; i < hands->size(); ++i) {
            const std::string p = "/hands/" + std::to_string(i);
            const Json& h = (*hands)[i];
            if (!h.is_object()) {
                c.problem(p, "expected an object");
                continue;
            }
            c.no_unknown_keys(h, p, {"hand", "position_mm", "edge_mm", "trajectory"});
            HandPlacement hp{};
            hp.hand = c.choice(h, p, "hand", {"left", "right"}) == "right" ? 1 : 0;
            hp.position_m = vec3(c, h, p, "position_mm", true, 1e-3, workspace).value_or(glm::dvec3{0.0});
            hp.edge_m = c.number(h, p, "edge_mm", {1, 200}, false).value_or(20) * 1e-3;
            hp.trajectory = c.string(h, p, "trajectory", false).value_or("");
            s.hands.push_back(hp);
        }
    }
    if (!c.ok()) return c.error();
    return s;
}

Result<SceneDef> load_scene(const std::filesystem::path& path) {
    auto text = assets::read_text_file(path);
    if (!text) return std::move(text).error();
    auto scene = parse_scene(*text, path.filename().string());
    if (scene) scene->file = path;
    return scene;
}

Result<void> apply_environment_overrides(systems::insertion::Covariates& environment, const std::vector<std::string>& settings) {
    systems::insertion::Covariates updated = environment;
    for (const auto& setting : settings) {
        const auto eq = setting.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == setting.size()) {
            return make_error(ErrorCode::invalid_argument, "--env '" + setting + "': expected name=value");
        }
        if (auto words = non_utf8_words("--env '" + utf8_or_replacement(setting) + "'", setting)) return make_error(ErrorCode::invalid_argument, *words);
        const std::string name = setting.substr(0, eq);
        const std::string value = setting.substr(eq + 1);
        double number = 0.0;
        const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), number);
        updated.numeric.erase(name);
        updated.category.erase(name);
        if (ec == std::errc{} && ptr == value.data() + value.size() && std::isfinite(number)) updated.numeric[name] = number;
        else updated.category[name] = value;
    }
    environment = std::move(updated);
    return Ok{};
}

Result<SceneDef> with_environment(Result<SceneDef> scene, const std::vector<std::string>& settings) {
    if (!scene) return scene;
    if (auto env = apply_environment_overrides(scene->environment, settings); !env) return std::move(env).error();
    return scene;
}

} // namespace ikebana::game
