#include "game/training/form_score.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/training/arrangement_score.hpp"

namespace ikebana::game {

using assets::Json;
using assets::JsonChecker;

namespace {

constexpr double pi = 3.14159265358979323846;
constexpr double deg = pi / 180.0;

double wrap_deg(double a) {
    a = std::fmod(a + 180.0, 360.0);
    if (a < 0) a += 360.0;
    return a - 180.0;
}

// Rounded for a reader: by multiplying with the inverse step, so that 87.3 prints as 87.3.
double round_to(double v, double step) {
    const double per_unit = std::round(1.0 / step);
    return std::round(v * per_unit) / per_unit;
}

std::string fmt(const char* f, auto... args) {
    char text[400];
    std::snprintf(text, sizeof text, f, args...);
    return text;
}

glm::dvec3 tip_of(const ArrangementStem& s) {
    if (!s.path_m.empty()) return s.path_m.back();
    return glm::dvec3(s.base_m, 0.0) + lesson_direction(s.tilt_rad, s.azimuth_rad) * s.length_m;
}

// The stem as a polyline from its base, kenzan coordinates.
std::vector<glm::dvec3> polyline(const ArrangementStem& s) {
    std::vector<glm::dvec3> p{glm::dvec3(s.base_m, 0.0)};
    if (s.path_m.empty()) p.push_back(tip_of(s));
    else p.insert(p.end(), s.path_m.begin(), s.path_m.end());
    return p;
}

// Where a polyline is at height z (its first crossing), if it reaches it.
std::optional<glm::dvec2> at_height(const std::vector<glm::dvec3>& p, double z) {
    for (std::size_t i = 1; i < p.size(); ++i) {
        const double z0 = p[i - 1].z, z1 = p[i].z;
        if ((z0 <= z && z <= z1) || (z1 <= z && z <= z0)) {
            const double t = std::abs(z1 - z0) < 1e-12 ? 0.0 : (z - z0) / (z1 - z0);
            return glm::dvec2(p[i - 1] + (p[i] - p[i - 1]) * t);
        }
    }
    return std::nullopt;
}

// How far a point on the kenzan's face is outside a region of it, metres (0: inside).
double outside_region(glm::dvec2 b, KenzanRegion r, glm::dvec2 size) {
    const glm::dvec2 h = 0.5 * size;
    // Each region as a box in the face; "front" is toward the viewer (-y). Halves overlap by a pin pitch
    // around the middle lines, so a stem on the line counts for both sides.
    const double m = 0.004;
    double x0 = -h.x, x1 = h.x, y0 = -h.y, y1 = h.y;
    switch (r) {
    case KenzanRegion::any: break;
    case KenzanRegion::centre: x0 = -h.x / 2, x1 = h.x / 2, y0 = -h.y / 2, y1 = h.y / 2; break;
    case KenzanRegion::front: y1 = m; break;
    case KenzanRegion::back: y0 = -m; break;
    case KenzanRegion::left: x1 = m; break;
    case KenzanRegion::right: x0 = -m; break;
    case KenzanRegion::front_left: x1 = m, y1 = m; break;
    case KenzanRegion::front_right: x0 = -m, y1 = m; break;
    case KenzanRegion::back_left: x1 = m, y0 = -m; break;
    case KenzanRegion::back_right: x0 = -m, y0 = -m; break;
    }
    const double dx = std::max({x0 - b.x, 0.0, b.x - x1});
    const double dy = std::max({y0 - b.y, 0.0, b.y - y1});
    return std::hypot(dx, dy);
}

std::string where_on_kenzan(glm::dvec2 b, glm::dvec2 size) {
    const double third_x = size.x / 6.0, third_y = size.y / 6.0;
    const std::string fb = b.y < -third_y ? "front" : b.y > third_y ? "back" : "";
    const std::string lr = b.x < -third_x ? "left" : b.x > third_x ? "right" : "";
    if (fb.empty() && lr.empty()) return "the centre";
    if (fb.empty()) return "the " + lr;
    if (lr.empty()) return "the " + fb;
    return "the " + fb + " " + lr;
}

bool segments_cross(glm::dvec2 a0, glm::dvec2 a1, glm::dvec2 b0, glm::dvec2 b1, glm::dvec2& at) {
    const glm::dvec2 r = a1 - a0, s = b1 - b0;
    const double d = r.x * s.y - r.y * s.x;
    if (std::abs(d) < 1e-15) return false;
    const glm::dvec2 q = b0 - a0;
    const double t = (q.x * s.y - q.y * s.x) / d;
    const double u = (q.x * r.y - q.y * r.x) / d;
    if (t < 0 || t > 1 || u < 0 || u > 1) return false;
    at = a0 + r * t;
    return true;
}

} // namespace

double water_level_m(const LessonDef& l, const KenzanFootprint& k) {
    if (l.container.shape == ContainerShape::vase) return 0.0;
    return l.container.water_depth_m - k.plate_thickness_m;
}

double band_points(double error, double tolerance, double max_points) {
    const double band = tolerance > 0.0 ? tolerance : 4.0;
    const double e = std::abs(error);
    if (e <= tolerance) return max_points;
    // From the band's edge to three times the band, linearly to nothing.
    return max_points * std::clamp(1.0 - (e - tolerance) / (2.0 * band), 0.0, 1.0);
}

// ---- the arrangement as JSON ----

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
        c.no_unknown_keys(s, p, {"role", "species", "base_mm", "length_mm", "tilt_deg", "azimuth_deg", "standing", "path_mm"});
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
        if (const Json* path = c.array(s, p, "path_mm", false)) {
            if (path->size() > max_path_points) c.problem(p + "/path_mm", "more than " + std::to_string(max_path_points) + " points");
            for (std::size_t j = 0; j < path->size() && j < max_path_points; ++j) {
                const Json& q = (*path)[j];
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
        a.stems.push_back(std::move(st));
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
        stems.push_back(j);
    }
    OJson out = {{"stems", stems}};
    if (a.kenzan_offset_m) out["kenzan_offset_mm"] = {round_to(a.kenzan_offset_m->x * 1e3, 0.1), round_to(a.kenzan_offset_m->y * 1e3, 0.1)};
    return out;
}
} // namespace

std::string arrangement_json(const Arrangement& a, int indent) { return arrangement_object(a).dump(indent) + "\n"; }

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
    return out.dump(indent) + "\n";
}

std::vector<std::string> FormScore::lines() const {
    std::vector<std::string> out;
    out.push_back(fmt("RESULT: %.0f / 100 (%s)", score, lesson.c_str()));
    // For each stem the criterion that lost most, or that it is within every band.
    std::vector<std::string> roles;
    for (const auto& c : criteria) {
        if (std::find(roles.begin(), roles.end(), c.stem) == roles.end()) roles.push_back(c.stem);
    }
    for (const auto& role : roles) {
        double earned = 0.0, possible = 0.0, worst_loss = 0.0;
        const Criterion* worst = nullptr;
        for (const auto& c : criteria) {
            if (c.stem != role) continue;
            earned += c.points;
            possible += c.max_points;
            if (c.max_points - c.points > worst_loss + 1e-9) {
                worst_loss = c.max_points - c.points;
                worst = &c;
            }
        }
        out.push_back(fmt("  %-9s %4.1f / %-4.0f %s", role.c_str(), earned, possible, worst ? worst->tip.c_str() : "within every band"));
    }
    for (const auto& r : rules) {
        out.push_back(fmt("  %-9s %s", r.ok ? "ok" : "rule", r.tip.c_str()));
    }
    return out;
}

// ---- scoring ----

namespace {

struct RoleCost {
    double cost = 0.0;
    bool allowed = true;
};

// How far a stem is from a role's bands (in bands), for choosing who plays which role.
RoleCost role_cost(const LessonDef& l, std::size_t role, const ArrangementStem& s, const KenzanFootprint& k) {
    const MainStemDef& m = l.stems[role];
    if (!m.species.empty() && std::find(m.species.begin(), m.species.end(), s.species) == m.species.end()) return {0.0, false};
    const double nominal = nominal_length_m(l, role);
    const double length_band = std::max(1e-3, m.length_ratio.tolerance / std::max(1e-9, m.length_ratio.target) * nominal);
    double cost = std::abs(s.length_m - nominal) / length_band;
    cost += std::abs(s.tilt_rad - m.tilt_rad.target) / std::max(deg, m.tilt_rad.tolerance);
    if (m.azimuth_rad) cost += std::abs(wrap_deg((s.azimuth_rad - m.azimuth_rad->target) / deg)) * deg / std::max(deg, m.azimuth_rad->tolerance);
    cost += outside_region(s.base_m, m.region, k.size_m) / 0.004;
    return {cost, true};
}

// Roles for stems with none given: the assignment of standing stems to the remaining roles with the
// smallest total cost (dynamic programming over stems and the set of roles filled: roles are few).
void assign_roles(const LessonDef& l, Arrangement& a, const KenzanFootprint& k) {
    const std::size_t n_roles = l.stems.size();
    std::vector<bool> taken(n_roles, false);
    for (const auto& s : a.stems) {
        for (std::size_t r = 0; r < n_roles; ++r) {
            if (s.role == l.stems[r].role) taken[r] = true;
        }
    }
    std::vector<std::size_t> free_stems;
    for (std::size_t i = 0; i < a.stems.size(); ++i) {
        if (a.stems[i].role.empty() && a.stems[i].standing) free_stems.push_back(i);
    }
    const std::size_t masks = std::size_t{1} << n_roles;
    const double unfilled = 1e6; // a role left empty costs more than any stem in it
    constexpr double inf = std::numeric_limits<double>::infinity();
    // best[i][mask]: the least cost with the first i free stems placed and `mask` roles filled by them.
    std::vector<std::vector<double>> best(free_stems.size() + 1, std::vector<double>(masks, inf));
    std::vector<std::vector<int>> choice(free_stems.size() + 1, std::vector<int>(masks, -1));
    best[0][0] = 0.0;
    for (std::size_t i = 0; i < free_stems.size(); ++i) {
        for (std::size_t mask = 0; mask < masks; ++mask) {
            if (best[i][mask] == inf) continue;
            // The stem supports (no role) ...
            if (best[i][mask] < best[i + 1][mask]) {
                best[i + 1][mask] = best[i][mask];
                choice[i + 1][mask] = -1;
            }
            // ... or plays a role still open.
            for (std::size_t r = 0; r < n_roles; ++r) {
                if (taken[r] || (mask & (std::size_t{1} << r))) continue;
                const RoleCost rc = role_cost(l, r, a.stems[free_stems[i]], k);
                if (!rc.allowed) continue;
                const std::size_t next = mask | (std::size_t{1} << r);
                if (best[i][mask] + rc.cost < best[i + 1][next]) {
                    best[i + 1][next] = best[i][mask] + rc.cost;
                    choice[i + 1][next] = static_cast<int>(r);
                }
            }
        }
    }
    std::size_t best_mask = 0;
    double best_total = inf;
    for (std::size_t mask = 0; mask < masks; ++mask) {
        const double total = best[free_stems.size()][mask] + unfilled * static_cast<double>(n_roles - static_cast<std::size_t>(__builtin_popcountll(mask)));
        if (total < best_total) {
            best_total = total;
            best_mask = mask;
        }
    }
    // Walk back: which role each free stem took.
    std::size_t mask = best_mask;
    for (std::size_t i = free_stems.size(); i > 0; --i) {
        // choice[i][mask] is how the best way into (i, mask) came: the role stem i-1 took, or -1 (it supports).
        const int r = choice[i][mask];
        if (r >= 0) {
            a.stems[free_stems[i - 1]].role = l.stems[static_cast<std::size_t>(r)].role;
            mask &= ~(std::size_t{1} << r);
        } else {
            a.stems[free_stems[i - 1]].role = "supporting";
        }
    }
    // A role no standing stem plays goes to the fallen stem nearest to it, so that its tips say it fell
    // rather than that nothing plays it.
    for (std::size_t r = 0; r < n_roles; ++r) {
        if (taken[r] || (best_mask & (std::size_t{1} << r))) continue;
        std::optional<std::size_t> nearest;
        double least = inf;
        for (std::size_t i = 0; i < a.stems.size(); ++i) {
            if (!a.stems[i].role.empty() || a.stems[i].standing) continue;
            const RoleCost rc = role_cost(l, r, a.stems[i], k);
            if (rc.allowed && rc.cost < least) {
                least = rc.cost;
                nearest = i;
            }
        }
        if (nearest) a.stems[*nearest].role = l.stems[r].role;
    }
    for (auto& s : a.stems) {
        if (s.role.empty()) s.role = "supporting"; // fallen stems no role is missing
    }
}

void score_stem(const LessonDef& l, std::size_t r, const ArrangementStem* s, const std::vector<const ArrangementStem*>& by_role,
                const KenzanFootprint& k, FormScore& out) {
    const MainStemDef& m = l.stems[r];
    const std::string& who = m.role;
    // The length's target: a ratio of the container, or of the stem that actually plays the role it follows.
    double base_m = l.container.size_m();
    std::string base_words = fmt("the container's size, %.0f mm", base_m * 1e3);
    if (m.length_of.kind == LengthBase::Kind::container_height) {
        base_m = l.container.depth_m;
        base_words = fmt("the container's height, %.0f mm", base_m * 1e3);
    } else if (m.length_of.kind == LengthBase::Kind::role) {
        const std::size_t of = m.length_of.role;
        const bool measured = by_role[of] && by_role[of]->standing;
        base_m = measured ? by_role[of]->length_m : nominal_length_m(l, of);
        base_words = fmt("%s%s, %.0f mm", l.stems[of].role.c_str(), measured ? "" : " as the form wants it", base_m * 1e3);
    }
    const double length_target_mm = base_m * m.length_ratio.target * 1e3;
    const double length_band_mm = base_m * m.length_ratio.tolerance * 1e3;
    Criterion length{who, "length_mm", length_target_mm, length_band_mm, {}, 0.0, l.length_points, {}};
    Criterion tilt{who, "tilt_deg", m.tilt_rad.target / deg, m.tilt_rad.tolerance / deg, {}, 0.0, l.tilt_points, {}};
    std::optional<Criterion> azimuth;
    if (m.azimuth_rad) azimuth = Criterion{who, "azimuth_deg", m.azimuth_rad->target / deg, m.azimuth_rad->tolerance / deg, {}, 0.0, l.azimuth_points, {}};
    Criterion region{who, "region_mm", 0.0, 0.0, {}, 0.0, l.region_points, {}};
    const bool present = s && s->standing;
    if (!s || !present) {
        const std::string why = !s ? "no stem plays it" : "it fell";
        const std::string todo = !s ? fmt("choose a material for it and cut it to %.0f mm above the kenzan", length_target_mm)
                                    : "push it deeper into the pins, or lean it less";
        length.tip = fmt("%s: %s: %s", who.c_str(), why.c_str(), todo.c_str());
        tilt.tip = fmt("%s: %s", who.c_str(), why.c_str());
        region.tip = tilt.tip;
        if (azimuth) azimuth->tip = tilt.tip;
        if (s) {
            length.measured = s->length_m * 1e3;
            tilt.measured = s->tilt_rad / deg;
        }
    } else {
        // Length
        const double mm = s->length_m * 1e3;
        length.measured = mm;
        length.points = band_points(mm - length_target_mm, length_band_mm, length.max_points);
        const std::string band = fmt("%.0f mm ±%.0f (%.2f × %s)", length_target_mm, length_band_mm, m.length_ratio.target, base_words.c_str());
        const std::string want = "the form wants " + band;
        if (std::abs(mm - length_target_mm) <= length_band_mm) length.tip = fmt("%s: %.0f mm long, within %s", who.c_str(), mm, band.c_str());
        else if (mm > length_target_mm) length.tip = fmt("%s: %.0f mm long, %s: cut it %.0f mm shorter", who.c_str(), mm, want.c_str(), mm - length_target_mm);
        else length.tip = fmt("%s: %.0f mm long, %s: it is %.0f mm short; use a longer material, or cut less off", who.c_str(), mm, want.c_str(), length_target_mm - mm);
        // Tilt
        const double t = s->tilt_rad / deg;
        tilt.measured = t;
        tilt.points = band_points(t - tilt.target, tilt.tolerance, tilt.max_points);
        const std::string lean = m.azimuth_rad ? " toward the " + direction_words(m.azimuth_rad->target) : "";
        if (std::abs(t - tilt.target) <= tilt.tolerance) {
            tilt.tip = fmt("%s: %.0f° from vertical, within the form's %.0f° ±%.0f°", who.c_str(), t, tilt.target, tilt.tolerance);
        } else if (t < tilt.target) {
            tilt.tip = fmt("%s: %.0f° from vertical, the form wants %.0f° ±%.0f°: tilt it further%s", who.c_str(), t, tilt.target, tilt.tolerance, lean.c_str());
        } else {
            tilt.tip = fmt("%s: %.0f° from vertical, the form wants %.0f° ±%.0f°: raise it toward upright", who.c_str(), t, tilt.target, tilt.tolerance);
        }
        // Direction: meaningless for a stem that stands straight up.
        if (azimuth) {
            const std::string want_dir = direction_words(azimuth->target);
            if (t < 1.0) {
                azimuth->measured.reset();
                azimuth->tip = fmt("%s: stands straight up, so it leans no way; the form leans it toward the %s (%.0f° ±%.0f°)", who.c_str(), want_dir.c_str(),
                                   azimuth->target, azimuth->tolerance);
            } else {
                const double a = s->azimuth_rad / deg;
                const double err = wrap_deg(a - azimuth->target);
                azimuth->measured = wrap_deg(a);
                azimuth->points = band_points(err, azimuth->tolerance, azimuth->max_points);
                if (std::abs(err) <= azimuth->tolerance) {
                    azimuth->tip = fmt("%s: leans toward the %s (%.0f°), within the form's %.0f° ±%.0f°", who.c_str(), direction_words(s->azimuth_rad).c_str(), wrap_deg(a),
                                       azimuth->target, azimuth->tolerance);
                } else {
                    azimuth->tip = fmt("%s: leans toward the %s (%.0f°), the form wants the %s (%.0f° ±%.0f°): turn it %.0f° to the %s", who.c_str(),
                                       direction_words(s->azimuth_rad).c_str(), wrap_deg(a), want_dir.c_str(), azimuth->target, azimuth->tolerance, std::abs(err),
                                       err > 0 ? "right (clockwise seen from above)" : "left (anticlockwise seen from above)");
                }
            }
        }
        // Place on the kenzan
        const double out_mm = outside_region(s->base_m, m.region, k.size_m) * 1e3;
        region.measured = out_mm;
        region.tolerance = 0.0;
        region.points = band_points(out_mm, 0.0, region.max_points);
        region.tip = out_mm <= 0.0 ? fmt("%s: enters %s of the kenzan, where the form puts it", who.c_str(), where_on_kenzan(s->base_m, k.size_m).c_str())
                                   : fmt("%s: enters %s of the kenzan, %.0f mm from %s, where the form puts it: move its base there", who.c_str(),
                                         where_on_kenzan(s->base_m, k.size_m).c_str(), out_mm, region_words(m.region).c_str());
    }
    out.criteria.push_back(length);
    out.criteria.push_back(tilt);
    if (azimuth) out.criteria.push_back(*azimuth);
    if (m.region != KenzanRegion::any) out.criteria.push_back(region);
}

RuleResult check_rule(const LessonDef& l, const RuleDef& rule, const Arrangement& a, const std::vector<const ArrangementStem*>& by_role,
                      const KenzanFootprint& k) {
    RuleResult r{rule_name(rule.kind), false, 0.0, rule.points, {}};
    std::vector<const ArrangementStem*> standing;
    for (const auto& s : a.stems) {
        if (s.standing) standing.push_back(&s);
    }
    switch (rule.kind) {
    case RuleKind::odd_main_stems: {
        std::size_t n = 0;
        std::string missing;
        for (std::size_t i = 0; i < by_role.size(); ++i) {
            if (by_role[i] && by_role[i]->standing) ++n;
            else missing += (missing.empty() ? "" : ", ") + l.stems[i].role;
        }
        r.ok = n % 2 == 1;
        r.tip = r.ok ? fmt("%zu main stems stand: an odd number, as the form wants", n)
                     : fmt("%zu main stems stand; the form wants an odd number%s%s", n, missing.empty() ? "" : ": add ", missing.c_str());
        break;
    }
    case RuleKind::no_crossing_front: {
        // The front view: x across, z up. Crossings low down, where every stem leaves the kenzan
        // together, do not count: only above a quarter of the shorter stem's height (and 30 mm).
        r.ok = true;
        r.tip = "no two stems cross in the front view";
        for (std::size_t i = 0; i < standing.size() && r.ok; ++i) {
            for (std::size_t j = i + 1; j < standing.size() && r.ok; ++j) {
                const auto p = polyline(*standing[i]), q = polyline(*standing[j]);
                const double low = std::max(0.03, 0.25 * std::min(p.back().z, q.back().z));
                for (std::size_t u = 1; u < p.size() && r.ok; ++u) {
                    for (std::size_t v = 1; v < q.size() && r.ok; ++v) {
                        glm::dvec2 at;
                        if (segments_cross({p[u - 1].x, p[u - 1].z}, {p[u].x, p[u].z}, {q[v - 1].x, q[v - 1].z}, {q[v].x, q[v].z}, at) && at.y > low) {
                            r.ok = false;
                            r.tip = fmt("%s and %s cross in the front view, %.0f mm above the kenzan: move one base across, or turn one the other way",
                                        standing[i]->role.c_str(), standing[j]->role.c_str(), at.y * 1e3);
                        }
                    }
                }
            }
        }
        break;
    }
    case RuleKind::kenzan_hidden_front: {
        // From the front, the kenzan's width is hidden by stems that lean toward the viewer and stay
        // low (tilted 45° or more): each hides the width between its base and its tip, and a head or
        // leaves of about 20 mm either side.
        std::vector<std::pair<double, double>> cover;
        for (const auto* s : standing) {
            const double az = wrap_deg(s->azimuth_rad / deg);
            if (s->tilt_rad < 45.0 * deg || std::abs(az) > 90.0) continue;
            const glm::dvec3 tip = tip_of(*s);
            cover.emplace_back(std::min(s->base_m.x, tip.x) - 0.02, std::max(s->base_m.x, tip.x) + 0.02);
        }
        std::sort(cover.begin(), cover.end());
        const double x0 = -0.5 * k.size_m.x, x1 = 0.5 * k.size_m.x;
        double covered = 0.0, reach = x0;
        double gap_from = x0, gap_to = x0, widest_gap = 0.0;
        for (const auto& [from, to] : cover) {
            const double f = std::max(from, reach), t = std::min(to, x1);
            if (f > reach && f - reach > widest_gap) {
                widest_gap = std::min(f, x1) - reach;
                gap_from = reach;
                gap_to = std::min(f, x1);
            }
            if (t > f) covered += t - f;
            reach = std::max(reach, std::min(to, x1));
        }
        if (x1 - reach > widest_gap) {
            widest_gap = x1 - reach;
            gap_from = reach;
            gap_to = x1;
        }
        const double part = covered / (x1 - x0);
        r.ok = part >= 0.8;
        r.tip = r.ok ? fmt("the kenzan is hidden from the front (%.0f %% of its width)", part * 100)
                     : fmt("the kenzan shows from the front (%.0f %% of its width hidden): add a low stem leaning toward the front between x = %.0f and %.0f mm",
                           part * 100, gap_from * 1e3, gap_to * 1e3);
        break;
    }
    case RuleKind::kenzan_off_centre: {
        const glm::dvec2 offset = a.kenzan_offset_m.value_or(l.kenzan_offset_m);
        const double radius = 0.5 * std::min(l.container.width_m, l.container.front_to_back_m);
        r.ok = glm::length(offset) >= 0.2 * radius;
        r.tip = r.ok ? fmt("the kenzan sits off the container's centre (%.0f mm from it), leaving open water", glm::length(offset) * 1e3)
                     : fmt("the kenzan sits in the container's centre (%.0f mm from it): move it toward a side, leaving open water", glm::length(offset) * 1e3);
        break;
    }
    case RuleKind::one_line_at_water: {
        // The main stems rise together from the water: the height above the water at which they first
        // spread wider than 15 mm.
        std::vector<std::vector<glm::dvec3>> lines;
        for (const auto* s : by_role) {
            if (s && s->standing) lines.push_back(polyline(*s));
        }
        const double water_z = water_level_m(l, k);
        double parts_at = 0.0;
        for (double z = 0.0; z < 0.5; z += 0.001) {
            std::vector<glm::dvec2> at;
            for (const auto& line : lines) {
                if (auto p = at_height(line, z)) at.push_back(*p);
            }
            double spread = 0.0;
            for (std::size_t i = 0; i < at.size(); ++i) {
                for (std::size_t j = i + 1; j < at.size(); ++j) spread = std::max(spread, glm::length(at[i] - at[j]));
            }
            if (spread > 0.015 || at.size() < lines.size() || lines.size() < 2) break;
            parts_at = z;
        }
        const double above_water_mm = (parts_at - water_z) * 1e3;
        r.ok = lines.size() >= 2 && parts_at - water_z >= rule.min_m && parts_at - water_z <= rule.max_m;
        if (lines.size() < 2) r.tip = "fewer than two main stems stand: there is no line at the water to judge";
        else if (r.ok) r.tip = fmt("the main stems rise as one line for %.0f mm above the water, as the form wants", above_water_mm);
        else r.tip = fmt("the main stems part %.0f mm above the water; the form keeps them one line for %.0f-%.0f mm before they spread", above_water_mm,
                         rule.min_m * 1e3, rule.max_m * 1e3);
        break;
    }
    case RuleKind::supporting_count: {
        std::size_t n = 0;
        std::string too_long;
        const ArrangementStem* limit = l.supporting.shorter_than_role ? by_role[*l.supporting.shorter_than_role] : nullptr;
        for (const auto* s : standing) {
            if (s->role != "supporting") continue;
            ++n;
            if (limit && s->length_m >= limit->length_m && too_long.empty()) {
                too_long = fmt("a supporting %s (%.0f mm) is as long as %s (%.0f mm): cut it shorter", s->species.c_str(), s->length_m * 1e3,
                               limit->role.c_str(), limit->length_m * 1e3);
            }
        }
        r.ok = n <= l.supporting.max_count && too_long.empty();
        if (n > l.supporting.max_count) r.tip = fmt("%zu supporting stems; the form allows %u: take some out", n, l.supporting.max_count);
        else if (!too_long.empty()) r.tip = too_long;
        else if (n == 0) r.tip = "no supporting stems";
        else r.tip = fmt("%zu supporting stem(s), each shorter than the main stem it supports", n);
        break;
    }
    }
    r.points = r.ok ? r.max_points : 0.0;
    return r;
}

} // namespace

Result<FormScore> score_form(const LessonDef& l, const Arrangement& arrangement, const KenzanFootprint& k, const std::string& label) {
    if (l.scoring != "form") return make_error(ErrorCode::invalid_argument, l.id + " is scored against its scene's sample, not a form");
    FormScore out;
    out.lesson = l.id;
    out.arrangement = arrangement;
    auto& stems = out.arrangement.stems;
    // Roles given in the arrangement must be the lesson's, each once.
    std::vector<const ArrangementStem*> by_role(l.stems.size(), nullptr);
    std::string roles = "";
    for (const auto& m : l.stems) roles += m.role + ", ";
    for (std::size_t i = 0; i < stems.size(); ++i) {
        const std::string& role = stems[i].role;
        if (role.empty() || role == "supporting") continue;
        const auto it = std::find_if(l.stems.begin(), l.stems.end(), [&](const MainStemDef& m) { return m.role == role; });
        if (it == l.stems.end()) {
            return make_error(ErrorCode::invalid_argument,
                              fmt("%s: /stems/%zu/role: \"%s\" is not a role of %s (%sor supporting)", label.c_str(), i, role.c_str(), l.id.c_str(), roles.c_str()));
        }
        for (std::size_t j = 0; j < i; ++j) {
            if (stems[j].role == role) {
                return make_error(ErrorCode::invalid_argument, fmt("%s: /stems/%zu/role: \"%s\" is already played by /stems/%zu", label.c_str(), i, role.c_str(), j));
            }
        }
    }
    assign_roles(l, out.arrangement, k);
    for (const auto& s : stems) {
        for (std::size_t r = 0; r < l.stems.size(); ++r) {
            if (s.role == l.stems[r].role) by_role[r] = &s;
        }
    }
    for (std::size_t r = 0; r < l.stems.size(); ++r) score_stem(l, r, by_role[r], by_role, k, out);
    for (const auto& rule : l.rules) out.rules.push_back(check_rule(l, rule, out.arrangement, by_role, k));
    double earned = 0.0, possible = 0.0;
    for (const auto& c : out.criteria) {
        earned += c.points;
        possible += c.max_points;
    }
    for (const auto& r : out.rules) {
        earned += r.points;
        possible += r.max_points;
    }
    out.score = possible > 0.0 ? 100.0 * earned / possible : 0.0;
    out.how = fmt("Each main stem earns up to %.0f points for its length, %.0f for its tilt, %.0f for the way it leans and %.0f for its place on the kenzan: "
                  "all of them inside the form's band, none at three times the band, in a straight line between. Each rule met earns its points. "
                  "The score is the points earned out of those possible (%.0f), as a percentage.",
                  l.length_points, l.tilt_points, l.azimuth_points, l.region_points, possible);
    return out;
}

FormScore score_sample(const LessonDef& l, const Arrangement& arrangement, const std::vector<SampleStem>& sample) {
    FormScore out;
    out.lesson = l.id;
    out.arrangement = arrangement;
    std::vector<ArrangedStem> arranged;
    for (const auto& s : arrangement.stems) {
        const glm::dvec3 base(s.base_m, 0.0);
        arranged.push_back({s.species, base, tip_of(s), s.standing, !s.standing});
    }
    const ArrangementScore result = score_arrangement(arranged, sample, glm::dvec3{0.0});
    const double share = sample.empty() ? 0.0 : 100.0 / static_cast<double>(sample.size());
    for (std::size_t i = 0; i < result.stems.size(); ++i) {
        const StemComparison& c = result.stems[i];
        const std::string who = fmt("%s_%zu", c.species.c_str(), i + 1);
        Criterion m{who, "match", 0.0, 1.0, {}, c.score / 100.0 * share, share, {}};
        if (c.note == "missing") {
            m.tip = fmt("%s: missing: no %s in the kenzan", who.c_str(), c.species.c_str());
        } else {
            // The comparison's errors in units of its tolerances (10 degrees, 20 mm of height, 8 mm of place).
            m.measured = std::hypot(c.direction_error_deg / 10.0, c.height_error_mm / 20.0, c.position_error_mm / 8.0);
            m.tip = fmt("%s: direction off by %.0f°, top %+.0f mm, place off by %.0f mm%s%s", who.c_str(), c.direction_error_deg, c.height_error_mm,
                        c.position_error_mm, c.note.empty() ? "" : ", ", c.note.c_str());
        }
        if (c.arranged) out.arrangement.stems[*c.arranged].role = who;
        out.criteria.push_back(m);
    }
    for (auto& s : out.arrangement.stems) {
        if (s.role.empty()) s.role = "supporting";
    }
    out.score = result.score;
    out.how = "Free practice against the sample (the paper's Figure 2): each sample stem is matched with the closest stem of its species; it scores "
              "100 × exp(-(d² + h² + p²) / 2), d the direction error in 10°, h the top's height error in 20 mm, p the place error in 8 mm; the score is "
              "the mean over the sample's stems. \"measured\" is sqrt(d² + h² + p²).";
    return out;
}

} // namespace ikebana::game

namespace ikebana::game {

namespace {

glm::dvec2 region_centre(KenzanRegion r, glm::dvec2 size, std::size_t index) {
    const double x = 0.25 * size.x, y = 0.25 * size.y;
    switch (r) {
    case KenzanRegion::centre: return {0, 0};
    case KenzanRegion::front: return {0, -y};
    case KenzanRegion::back: return {0, y};
    case KenzanRegion::left: return {-x, 0};
    case KenzanRegion::right: return {x, 0};
    case KenzanRegion::front_left: return {-x, -y};
    case KenzanRegion::front_right: return {x, -y};
    case KenzanRegion::back_left: return {-x, y};
    case KenzanRegion::back_right: return {x, y};
    case KenzanRegion::any: break;
    }
    // Anywhere: side by side about the centre, a pin row apart.
    return {(static_cast<double>(index) - 1.0) * 0.008, 0.004};
}

// A stem that rises `rise_m` straight up, then leans so that the line from its base to its tip is
// tilted `tilt_rad`: the angle of its upper part, by bisection.
std::vector<glm::dvec3> risen_path(glm::dvec2 base, double length_m, double rise_m, double tilt_rad, double azimuth_rad) {
    const double upper = length_m - rise_m;
    const auto chord_tilt = [&](double lean) {
        const glm::dvec3 d = lesson_direction(lean, azimuth_rad) * upper;
        return std::atan2(std::hypot(d.x, d.y), rise_m + d.z);
    };
    double lo = 0.0, hi = 3.14159265358979323846 / 2.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (chord_tilt(mid) < tilt_rad ? lo : hi) = mid;
    }
    const glm::dvec3 knee(base, rise_m);
    return {knee, knee + lesson_direction(lo, azimuth_rad) * upper};
}

// Stems that rise as one line stand on neighbouring spots of a 3 x 3 block a pin row apart, placed so
// that their lines stay together longest once they part, each toward its own side at its own rate
// (`ways`: the sideways run of a stem per unit of height): of every way to put them there, the one whose
// widest gap, summed over a few heights above the base, is smallest (ties: the first found), of those
// whose lines never come closer than a pin row (a stem does not go through another). Two stems parting
// to opposite sides thus start each on the side the other leans to, a little aside, and pass beside
// each other before they part (the shoka's soe and tai: 8 mm apart at the base, 5.7 at the closest).
std::vector<glm::dvec2> one_line_bases(const std::vector<glm::dvec2>& ways) {
    constexpr double pitch_m = 0.004;
    std::vector<glm::dvec2> spots;
    for (int j = -1; j <= 1; ++j) {
        for (int i = -1; i <= 1; ++i) spots.push_back(glm::dvec2{i, j} * pitch_m);
    }
    std::vector<glm::dvec2> best, now;
    if (ways.size() > spots.size()) {
        for (std::size_t i = 0; i < ways.size(); ++i) best.push_back({(static_cast<double>(i) - 1.0) * pitch_m, 0.0});
        return best;
    }
    double best_cost = std::numeric_limits<double>::infinity();
    std::vector<bool> taken(spots.size(), false);
    // Infinite for lines that would pass through each other (closer than a pin row on their way up).
    const auto cost = [&] {
        for (std::size_t a = 0; a < now.size(); ++a) {
            for (std::size_t b = a + 1; b < now.size(); ++b) {
                for (int mm = 0; mm <= 60; ++mm) {
                    if (glm::length((now[a] + mm * 1e-3 * ways[a]) - (now[b] + mm * 1e-3 * ways[b])) < 0.9 * pitch_m) return std::numeric_limits<double>::infinity();
                }
            }
        }
        double sum = 0.0;
        for (double z : {0.0, 0.01, 0.02, 0.03}) {
            double widest = 0.0;
            for (std::size_t a = 0; a < now.size(); ++a) {
                for (std::size_t b = a + 1; b < now.size(); ++b) widest = std::max(widest, glm::length((now[a] + z * ways[a]) - (now[b] + z * ways[b])));
            }
            sum += widest;
        }
        return sum;
    };
    const std::function<void()> place = [&] {
        if (now.size() == ways.size()) {
            const double c = cost();
            if (c < best_cost - 1e-12) {
                best_cost = c;
                best = now;
            }
            return;
        }
        for (std::size_t i = 0; i < spots.size(); ++i) {
            if (taken[i]) continue;
            taken[i] = true;
            now.push_back(spots[i]);
            place();
            now.pop_back();
            taken[i] = false;
        }
    };
    place();
    if (best.empty()) { // no way at all (cannot happen with nine spots and a finite cost): the plain row
        for (std::size_t i = 0; i < ways.size(); ++i) best.push_back({(static_cast<double>(i) - 1.0) * pitch_m, 0.0});
    }
    return best;
}

} // namespace

double lean_above_rise_rad(const ArrangementStem& s) {
    if (s.path_m.size() != 2) return 0.0;
    return std::acos(std::clamp(glm::normalize(s.path_m[1] - s.path_m[0]).z, -1.0, 1.0));
}

Arrangement model_arrangement(const LessonDef& l, const KenzanFootprint& k) {
    Arrangement a;
    a.kenzan_offset_m = l.kenzan_offset_m;
    const auto rule = [&](RuleKind kind) -> const RuleDef* {
        for (const auto& r : l.rules) {
            if (r.kind == kind) return &r;
        }
        return nullptr;
    };
    const RuleDef* one_line = rule(RuleKind::one_line_at_water);
    for (std::size_t i = 0; i < l.stems.size(); ++i) {
        const MainStemDef& m = l.stems[i];
        ArrangementStem s;
        s.role = m.role;
        s.species = m.species.empty() ? (l.materials.empty() ? "" : l.materials.front().species) : m.species.front();
        s.length_m = nominal_length_m(l, i);
        s.tilt_rad = m.tilt_rad.target;
        s.azimuth_rad = m.azimuth_rad ? m.azimuth_rad->target : 0.0;
        // Stems that rise as one line share a point (below); the others take their region's centre.
        s.base_m = region_centre(m.region, k.size_m, i);
        if (one_line) {
            const double rise = water_level_m(l, k) + 0.5 * (one_line->min_m + one_line->max_m);
            if (rise < s.length_m) s.path_m = risen_path({0.0, 0.0}, s.length_m, rise, s.tilt_rad, s.azimuth_rad);
        }
        a.stems.push_back(std::move(s));
    }
    if (one_line) {
        std::vector<glm::dvec2> ways;
        for (const auto& s : a.stems) {
            const glm::dvec3 d = s.path_m.size() == 2 ? glm::normalize(s.path_m[1] - s.path_m[0]) : lesson_direction(s.tilt_rad, s.azimuth_rad);
            ways.push_back(glm::dvec2{d.x, d.y} / std::max(d.z, 0.1));
        }
        const auto bases = one_line_bases(ways);
        for (std::size_t i = 0; i < a.stems.size(); ++i) {
            auto& s = a.stems[i];
            for (auto& q : s.path_m) q += glm::dvec3(bases[i], 0.0); // its path was drawn from (0, 0)
            s.base_m = bases[i];
        }
    }
    if (rule(RuleKind::kenzan_hidden_front)) {
        // Supporting stems from the materials no main stem plays, low and leaning toward the viewer,
        // across the kenzan's front from left to right until it is hidden.
        std::string filler = l.materials.empty() ? "" : l.materials.back().species;
        double shortest = 1e9;
        for (const auto& s : a.stems) shortest = std::min(shortest, s.length_m);
        const std::size_t room = l.supporting.max_count;
        for (std::size_t n = 0; n < room; ++n) {
            if (check_rule(l, *rule(RuleKind::kenzan_hidden_front), a, {}, k).ok) break;
            double x = -0.5 * k.size_m.x + 0.02 + 0.04 * static_cast<double>(n);
            if (x > 0.5 * k.size_m.x) break;
            ArrangementStem s;
            s.role = "supporting";
            s.species = filler;
            s.base_m = {x, -0.5 * k.size_m.y + 0.006};
            // Short and not too low: a flower's head bends a long low stem over.
            s.length_m = std::min(0.12, 0.35 * shortest);
            s.tilt_rad = 55.0 * 3.14159265358979323846 / 180.0;
            s.azimuth_rad = 0.0;
            a.stems.push_back(std::move(s));
        }
    }
    return a;
}

} // namespace ikebana::game
