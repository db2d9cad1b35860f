// An arrangement as JSON, read and written, and a form score's JSON, which holds one.
#include "game/training/arrangement.hpp"

#include <algorithm>
#include <cmath>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/training/form_score.hpp"
#include "game/training/stem_geometry.hpp"

namespace ikebana::game {

using assets::Json;
using assets::JsonChecker;
using training::deg;

namespace {

// Rounded for a reader: by multiplying with the inverse step, so that 87.3 prints as 87.3.
double round_to(double v, double step) {
    const double per_unit = std::round(1.0 / step);
    return std::round(v * per_unit) / per_unit;
}

void read_path(JsonChecker& c, const Json& path, const std::string& p, ArrangementStem& st) {
    if (path.size() > max_path_points) c.problem(p + "/path_mm", "more than " + std::to_string(max_path_points) + " points");
    for (std::size_t j = 0; j < path.size() && j < max_path_points; ++j) {
        const Json& q = path[j];
        const std::string qp = p + "/path_mm/" + std::to_string(j);
        if (!q.is_array() || q.size() != 3 || !std::all_of(q.begin(), q.end(), [](const Json& v) { return v.is_number(); })) {
            c.problem(qp, "expected [x, y, z] in mm, got " + JsonChecker::describe(q));
            continue;
        }
        const glm::dvec3 v{q[0].get<double>(), q[1].get<double>(), q[2].get<double>()};
        if (!std::isfinite(v.x + v.y + v.z) || glm::any(glm::greaterThan(glm::abs(v), glm::dvec3(3000.0)))) {
            c.problem(qp, "expected coordinates within 3000 mm");
            continue;
        }
        st.path_m.push_back(v * 1e-3);
    }
}

void read_leaf_heights(JsonChecker& c, const Json& heights, const std::string& p, ArrangementStem& st) {
    if (heights.size() > max_leaf_heights) c.problem(p + "/leaf_heights_mm", "more than " + std::to_string(max_leaf_heights) + " leaves");
    for (std::size_t j = 0; j < heights.size() && j < max_leaf_heights; ++j) {
        const Json& h = heights[j];
        if (!h.is_number() || !std::isfinite(h.get<double>()) || std::abs(h.get<double>()) > 3000.0) {
            c.problem(p + "/leaf_heights_mm/" + std::to_string(j), "expected a height within 3000 mm, got " + JsonChecker::describe(h));
            continue;
        }
        st.leaf_heights_m.push_back(h.get<double>() * 1e-3);
    }
}

ArrangementStem read_stem(JsonChecker& c, const Json& s, const std::string& p) {
    c.no_unknown_keys(s, p, {"role", "species", "base_mm", "length_mm", "tilt_deg", "azimuth_deg", "standing", "path_mm", "leaf_heights_mm"});
    ArrangementStem st;
    st.role = c.string(s, p, "role", false).value_or("");
    st.species = c.string(s, p, "species").value_or("");
    const auto b = c.numbers(s, p, "base_mm", {-500, 500}, 2);
    if (b && b->size() != 2) c.problem(p + "/base_mm", "expected [x, y]");
    else if (b) st.base_m = glm::dvec2{(*b)[0], (*b)[1]} * 1e-3;
    st.length_m = c.number(s, p, "length_mm", {0, 3000}).value_or(0) * 1e-3;
    st.tilt_rad = c.number(s, p, "tilt_deg", {0, 180}).value_or(0) * deg;
    st.azimuth_rad = c.number(s, p, "azimuth_deg", {-360, 360}).value_or(0) * deg;
    st.standing = c.boolean(s, p, "standing", false).value_or(true);
    if (const Json* path = c.array(s, p, "path_mm", false)) read_path(c, *path, p, st);
    if (const Json* heights = c.array(s, p, "leaf_heights_mm", false)) read_leaf_heights(c, *heights, p, st);
    return st;
}

} // namespace

Result<Arrangement> parse_arrangement(std::string_view text, const std::string& label) {
    JsonChecker c(label);
    const auto root = c.parse_object(text);
    if (!root) return c.error();
    const Json* top = &*root;
    std::string base;
    if (root->contains("arrangement")) {
        // A whole result: its arrangement is read, what was scored is not (it is scored again).
        c.no_unknown_keys(*root, "", {"lesson", "score", "criteria", "rules", "arrangement", "how"});
        top = c.object(*root, "", "arrangement");
        base = "/arrangement";
        if (!top) return c.error();
    }
    c.no_unknown_keys(*top, base, {"stems", "kenzan_offset_mm", "notes"});
    Arrangement a;
    if (top->contains("kenzan_offset_mm")) {
        const auto k = c.numbers(*top, base, "kenzan_offset_mm", {-1000, 1000}, 2);
        if (k && k->size() != 2) c.problem(base + "/kenzan_offset_mm", "expected [x, y]");
        else if (k) a.kenzan_offset_m = glm::dvec2{(*k)[0], (*k)[1]} * 1e-3;
    }
    const Json* stems = c.array(*top, base, "stems");
    if (stems && stems->size() > max_arrangement_stems) {
        c.problem(base + "/stems", std::to_string(stems->size()) + " stems, more than the " + std::to_string(max_arrangement_stems) + " an arrangement may have");
    }
    for (std::size_t i = 0; stems && i < stems->size() && i < max_arrangement_stems; ++i) {
        const std::string p = base + "/stems/" + std::to_string(i);
        const Json& s = (*stems)[i];
        if (!s.is_object()) {
            c.problem(p, "expected an object, got " + JsonChecker::describe(s));
            continue;
        }
        a.stems.push_back(read_stem(c, s, p));
    }
    if (!c.ok()) return c.error();
    return a;
}

Result<Arrangement> load_arrangement(const std::filesystem::path& path) {
    auto text = assets::read_text_file(path, 16u << 20);
    if (!text) return std::move(text).error();
    return parse_arrangement(*text, path.filename().string());
}

using OJson = nlohmann::ordered_json; // outputs keep the order a reader expects

namespace {
OJson arrangement_object(const Arrangement& a) {
    OJson stems = OJson::array();
    for (const auto& s : a.stems) {
        OJson j = {{"role", s.role},
                  {"species", s.species},
                  {"base_mm", {round_to(s.base_m.x * 1e3, 0.1), round_to(s.base_m.y * 1e3, 0.1)}},
                  {"length_mm", round_to(s.length_m * 1e3, 0.1)},
                  {"tilt_deg", round_to(s.tilt_rad / deg, 0.1)},
                  {"azimuth_deg", round_to(s.azimuth_rad / deg, 0.1)},
                  {"standing", s.standing}};
        if (!s.path_m.empty()) {
            OJson path = OJson::array();
            for (const auto& q : s.path_m) path.push_back({round_to(q.x * 1e3, 0.1), round_to(q.y * 1e3, 0.1), round_to(q.z * 1e3, 0.1)});
            j["path_mm"] = path;
        }
        if (!s.leaf_heights_m.empty()) {
            OJson heights = OJson::array();
            for (const double h : s.leaf_heights_m) heights.push_back(round_to(h * 1e3, 0.1));
            j["leaf_heights_mm"] = heights;
        }
        stems.push_back(j);
    }
    OJson out = {{"stems", stems}};
    if (a.kenzan_offset_m) out["kenzan_offset_mm"] = {round_to(a.kenzan_offset_m->x * 1e3, 0.1), round_to(a.kenzan_offset_m->y * 1e3, 0.1)};
    return out;
}
} // namespace

std::string arrangement_json(const Arrangement& a, int indent) { return assets::json_text(arrangement_object(a), indent) + "\n"; }

std::string FormScore::json(int indent) const {
    OJson crit = OJson::array();
    for (const auto& c : criteria) {
        crit.push_back({{"stem", c.stem},
                        {"name", c.name},
                        {"target", round_to(c.target, 0.1)},
                        {"tolerance", round_to(c.tolerance, 0.1)},
                        {"measured", c.measured ? OJson(round_to(*c.measured, 0.1)) : OJson(nullptr)},
                        {"points", round_to(c.points, 0.01)},
                        {"max_points", c.max_points},
                        {"tip", c.tip}});
    }
    OJson rl = OJson::array();
    for (const auto& r : rules) rl.push_back({{"name", r.name}, {"ok", r.ok}, {"points", round_to(r.points, 0.01)}, {"max_points", r.max_points}, {"tip", r.tip}});
    const OJson out = {{"lesson", lesson}, {"score", round_to(score, 0.1)}, {"how", how}, {"criteria", crit}, {"rules", rl}, {"arrangement", arrangement_object(arrangement)}};
    return assets::json_text(out, indent) + "\n";
}

} // namespace ikebana::game
