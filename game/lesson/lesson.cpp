#include "game/lesson/lesson.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/asset_paths.hpp"
#include "game/kenzan/kenzan_layout.hpp"
#include "game/scene/scene.hpp"
#include "game/species/species.hpp"

namespace ikebana::game {

using assets::Json;
using assets::JsonChecker;

namespace {

constexpr double deg = 3.14159265358979323846 / 180.0;

const std::vector<std::string> region_names = {"any",   "centre",     "front",       "back",      "left",
                                               "right", "front_left", "front_right", "back_left", "back_right"};
const std::vector<std::string> rule_names = {"odd_main_stems",    "no_crossing_front", "kenzan_hidden_front",  "kenzan_off_centre",
                                             "one_line_at_water", "supporting_count",  "no_leaves_under_water"};

// Ids name files in assets/: letters, digits and underscores only, so that no id reaches outside it.
bool plain_id(const std::string& s) {
    return !s.empty() && s.size() <= 64 &&
           std::all_of(s.begin(), s.end(), [](char ch) { return (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_'; });
}

std::optional<Band> band(JsonChecker& c, const Json& parent, const std::string& path, const char* key, assets::NumberRange target,
                         assets::NumberRange tolerance, double scale, bool required) {
    const Json* b = c.object(parent, path, key, required);
    if (!b) return std::nullopt;
    const std::string p = path + "/" + key;
    c.no_unknown_keys(*b, p, {"target", "tolerance"});
    const auto t = c.number(*b, p, "target", target);
    const auto tol = c.number(*b, p, "tolerance", tolerance);
    if (!t || !tol) return std::nullopt;
    return Band{*t * scale, *tol * scale};
}

void parse_main_stems(JsonChecker& c, const Json& root, LessonDef& l) {
    const Json* stems = c.array(root, "", "main_stems");
    if (!stems) return;
    if (stems->empty() || stems->size() > max_lesson_stems) {
        c.problem("/main_stems", "expected 1 to " + std::to_string(max_lesson_stems) + " main stems, got " + std::to_string(stems->size()));
        if (!stems->empty()) return;
    }
    std::map<std::string, std::size_t> roles;
    for (std::size_t i = 0; i < stems->size(); ++i) {
        const std::string p = "/main_stems/" + std::to_string(i);
        const Json& s = (*stems)[i];
        if (!s.is_object()) {
            c.problem(p, "expected an object, got " + JsonChecker::describe(s));
            continue;
        }
        c.no_unknown_keys(s, p, {"role", "label", "species", "length", "tilt_deg", "azimuth_deg", "region"});
        MainStemDef m;
        m.role = c.string(s, p, "role").value_or("");
        if (!m.role.empty() && !plain_id(m.role)) c.problem(p + "/role", "expected lower-case letters, digits and _, got \"" + m.role + "\"");
        if (!m.role.empty() && roles.contains(m.role)) c.problem(p + "/role", "\"" + m.role + "\" is already the role of /main_stems/" + std::to_string(roles[m.role]));
        m.label = c.string(s, p, "label", false).value_or(m.role);
        if (const Json* species = c.array(s, p, "species", false)) {
            for (std::size_t j = 0; j < species->size(); ++j) {
                const Json& id = (*species)[j];
                if (!id.is_string() || !plain_id(id.get<std::string>())) {
                    c.problem(p + "/species/" + std::to_string(j), "expected a species id, got " + JsonChecker::describe(id));
                } else {
                    m.species.push_back(id.get<std::string>());
                }
            }
        }
        if (const Json* length = c.object(s, p, "length")) {
            const std::string lp = p + "/length";
            c.no_unknown_keys(*length, lp, {"ratio", "of", "tolerance", "also"});
            const auto ratio = c.number(*length, lp, "ratio", {0.05, 10});
            const auto tol = c.number(*length, lp, "tolerance", {0, 5});
            if (ratio && tol) m.length_ratio = Band{*ratio, *tol};
            if (const Json* also = c.array(*length, lp, "also", false)) {
                for (std::size_t j = 0; j < also->size() && j < 4; ++j) {
                    const Json& r = (*also)[j];
                    if (!r.is_number() || !std::isfinite(r.get<double>()) || r.get<double>() < 0.05 || r.get<double>() > 10) {
                        c.problem(lp + "/also/" + std::to_string(j), "expected a ratio in [0.05, 10], got " + JsonChecker::describe(r));
                    } else {
                        m.length_also.push_back(r.get<double>());
                    }
                }
                if (also->size() > 4) c.problem(lp + "/also", "more than 4 other ratios");
            }
            const auto of = c.string(*length, lp, "of");
            if (of == "container_size") {
                m.length_of.kind = LengthBase::Kind::container_size;
            } else if (of == "container_height") {
                m.length_of.kind = LengthBase::Kind::container_height;
            } else if (of) {
                const auto earlier = roles.find(*of);
                if (earlier == roles.end()) {
                    c.problem(lp + "/of", "expected \"container_size\", \"container_height\" or the role of an earlier main stem, got \"" + *of + "\"");
                } else {
                    m.length_of = {LengthBase::Kind::role, earlier->second};
                }
            }
        }
        if (auto tilt = band(c, s, p, "tilt_deg", {0, 90}, {0, 90}, deg, true)) m.tilt_rad = *tilt;
        m.azimuth_rad = band(c, s, p, "azimuth_deg", {-180, 180}, {0, 180}, deg, false);
        const auto region = c.choice(s, p, "region", region_names, false).value_or("any");
        m.region = static_cast<KenzanRegion>(std::find(region_names.begin(), region_names.end(), region) - region_names.begin());
        if (!m.role.empty()) roles.emplace(m.role, i);
        l.stems.push_back(std::move(m));
    }
}

void parse_rules(JsonChecker& c, const Json& root, LessonDef& l, const std::map<std::string, std::size_t>& roles) {
    if (const Json* supporting = c.object(root, "", "supporting", false)) {
        c.no_unknown_keys(*supporting, "/supporting", {"max_count", "shorter_than", "label"});
        l.supporting.label = c.string(*supporting, "/supporting", "label", false).value_or(l.supporting.label);
        l.supporting.max_count = static_cast<std::uint32_t>(c.integer(*supporting, "/supporting", "max_count", 0, 100).value_or(0));
        if (const auto role = c.string(*supporting, "/supporting", "shorter_than", false)) {
            if (const auto it = roles.find(*role); it != roles.end()) l.supporting.shorter_than_role = it->second;
            else c.problem("/supporting/shorter_than", "\"" + *role + "\" is not the role of a main stem");
        }
    }
    const Json* rules = c.array(root, "", "rules", false);
    if (!rules) return;
    for (std::size_t i = 0; i < rules->size() && i < 32; ++i) {
        const std::string p = "/rules/" + std::to_string(i);
        const Json& r = (*rules)[i];
        if (!r.is_object()) {
            c.problem(p, "expected an object, got " + JsonChecker::describe(r));
            continue;
        }
        const auto name = c.choice(r, p, "rule", rule_names);
        if (!name) continue;
        RuleDef rule{static_cast<RuleKind>(std::find(rule_names.begin(), rule_names.end(), *name) - rule_names.begin())};
        if (rule.kind == RuleKind::one_line_at_water) {
            c.no_unknown_keys(r, p, {"rule", "points", "min_mm", "max_mm"});
            rule.min_m = c.number(r, p, "min_mm", {1, 500}).value_or(0) * 1e-3;
            rule.max_m = c.number(r, p, "max_mm", {1, 500}).value_or(0) * 1e-3;
            if (rule.max_m < rule.min_m) c.problem(p + "/max_mm", "is below min_mm");
        } else if (rule.kind == RuleKind::kenzan_hidden_front) {
            c.no_unknown_keys(r, p, {"rule", "points", "by"});
            rule.supporting_only = c.choice(r, p, "by", {"any_stem", "supporting"}, false).value_or("any_stem") == "supporting";
        } else {
            c.no_unknown_keys(r, p, {"rule", "points"});
        }
        rule.points = c.number(r, p, "points", {0, 100}, false).value_or(4.0);
        if (std::any_of(l.rules.begin(), l.rules.end(), [&](const RuleDef& e) { return e.kind == rule.kind; })) {
            c.problem(p + "/rule", "\"" + *name + "\" is checked twice");
        }
        l.rules.push_back(rule);
    }
    if (rules->size() > 32) c.problem("/rules", "more than 32 rules");
}

} // namespace

Result<LessonDef> parse_lesson(std::string_view text, const std::string& label) {
    JsonChecker c(label);
    const auto root = c.parse_object(text);
    if (!root) return c.error();
    c.no_unknown_keys(*root, "", {"format", "id", "title", "school", "source", "summary", "level", "scoring", "scene", "container", "kenzan",
                                  "materials", "main_stems", "supporting", "rules", "points", "notes"});
    const auto format = c.string(*root, "", "format");
    if (format && *format != "ikebana-lesson/1") c.problem("/format", "expected \"ikebana-lesson/1\", got \"" + *format + "\"");
    LessonDef l;
    l.id = c.string(*root, "", "id").value_or("");
    if (!l.id.empty() && !plain_id(l.id)) c.problem("/id", "expected lower-case letters, digits and _, got \"" + l.id + "\"");
    l.title = c.string(*root, "", "title").value_or("");
    l.school = c.string(*root, "", "school").value_or("");
    l.source = c.string(*root, "", "source").value_or("");
    l.summary = c.string(*root, "", "summary", false).value_or("");
    l.level = static_cast<int>(c.integer(*root, "", "level", 1, 5, false).value_or(3));
    l.scoring = c.choice(*root, "", "scoring", {"form", "sample"}, false).value_or("form");
    const bool form = l.scoring == "form";
    if (form) {
        if (root->contains("scene")) c.problem("/scene", "only a lesson scored against a sample (\"scoring\": \"sample\") names a scene");
    } else {
        l.scene = c.string(*root, "", "scene").value_or("");
        for (const char* key : {"main_stems", "supporting", "rules", "points"}) {
            if (root->contains(key)) c.problem(std::string("/") + key, "a lesson scored against its scene's sample has no form to describe");
        }
    }
    if (const Json* box = c.object(*root, "", "container", form)) parse_container(c, *box, "/container", l.container);
    if (const Json* k = c.object(*root, "", "kenzan", form)) {
        c.no_unknown_keys(*k, "/kenzan", {"layout", "offset_mm"});
        l.kenzan_layout = c.string(*k, "/kenzan", "layout").value_or("standard");
        if (!plain_id(l.kenzan_layout)) c.problem("/kenzan/layout", "expected a kenzan layout id, got \"" + l.kenzan_layout + "\"");
        const auto offset = c.numbers(*k, "/kenzan", "offset_mm", {-1000, 1000}, 2);
        if (offset && offset->size() != 2) c.problem("/kenzan/offset_mm", "expected [x, y]");
        else if (offset) l.kenzan_offset_m = glm::dvec2{(*offset)[0], (*offset)[1]} * 1e-3;
    }
    if (const Json* materials = c.array(*root, "", "materials", form)) {
        if (materials->size() > max_lesson_materials) c.problem("/materials", "more than " + std::to_string(max_lesson_materials) + " materials");
        for (std::size_t i = 0; i < materials->size() && i < max_lesson_materials; ++i) {
            const std::string p = "/materials/" + std::to_string(i);
            const Json& m = (*materials)[i];
            if (!m.is_object()) {
                c.problem(p, "expected an object, got " + JsonChecker::describe(m));
                continue;
            }
            c.no_unknown_keys(m, p, {"species", "count", "length_mm"});
            MaterialDef md;
            md.species = c.string(m, p, "species").value_or("");
            if (!md.species.empty() && !plain_id(md.species)) c.problem(p + "/species", "expected a species id, got \"" + md.species + "\"");
            md.count = static_cast<std::uint32_t>(c.integer(m, p, "count", 1, 20, false).value_or(1));
            md.length_m = c.number(m, p, "length_mm", {20, 2000}, false).value_or(0) * 1e-3;
            l.materials.push_back(md);
        }
    }
    std::map<std::string, std::size_t> roles;
    if (form) {
        parse_main_stems(c, *root, l);
        for (std::size_t i = 0; i < l.stems.size(); ++i) roles.emplace(l.stems[i].role, i);
        parse_rules(c, *root, l, roles);
        if (const Json* points = c.object(*root, "", "points", false)) {
            c.no_unknown_keys(*points, "/points", {"length", "tilt", "azimuth", "region"});
            l.length_points = c.number(*points, "/points", "length", {0, 100}, false).value_or(l.length_points);
            l.tilt_points = c.number(*points, "/points", "tilt", {0, 100}, false).value_or(l.tilt_points);
            l.azimuth_points = c.number(*points, "/points", "azimuth", {0, 100}, false).value_or(l.azimuth_points);
            l.region_points = c.number(*points, "/points", "region", {0, 100}, false).value_or(l.region_points);
        }
        if (c.ok() && l.container.shape != ContainerShape::vase) {
            // The kenzan's centre must be inside the container (its size is checked on load, with its layout).
            const glm::dvec2 half{0.5 * l.container.width_m, 0.5 * l.container.front_to_back_m};
            if (std::abs(l.kenzan_offset_m.x) > half.x || std::abs(l.kenzan_offset_m.y) > half.y) {
                c.problem("/kenzan/offset_mm", "puts the kenzan's centre outside the container");
            }
        }
    }
    if (!c.ok()) return c.error();
    return l;
}

double nominal_length_m(const LessonDef& l, std::size_t i) {
    const MainStemDef& m = l.stems.at(i);
    double base = l.container.size_m();
    if (m.length_of.kind == LengthBase::Kind::container_height) base = l.container.depth_m;
    if (m.length_of.kind == LengthBase::Kind::role && m.length_of.role < i) base = nominal_length_m(l, m.length_of.role);
    return base * m.length_ratio.target;
}

Result<LessonDef> load_lesson_file(const std::filesystem::path& path) {
    auto text = assets::read_text_file(path);
    if (!text) return std::move(text).error();
    const std::string label = path.filename().string();
    auto lesson = parse_lesson(*text, label);
    if (!lesson) return lesson;
    lesson->file = path;
    std::vector<std::string> problems;
    // What it names must exist, and be able to make the form.
    std::map<std::string, double> longest_m;
    for (std::size_t i = 0; i < lesson->materials.size(); ++i) {
        const auto& m = lesson->materials[i];
        const auto species = load_species(m.species);
        if (!species) {
            problems.push_back(label + ": /materials/" + std::to_string(i) + "/species: no species \"" + m.species + "\" (" +
                               species.error().message + ")");
            continue;
        }
        const double length = m.length_m > 0.0 ? m.length_m : species->length_m;
        longest_m[m.species] = std::max(longest_m[m.species], length);
    }
    for (std::size_t i = 0; i < lesson->stems.size(); ++i) {
        const auto& stem = lesson->stems[i];
        for (std::size_t j = 0; j < stem.species.size(); ++j) {
            if (!longest_m.contains(stem.species[j])) {
                problems.push_back(label + ": /main_stems/" + std::to_string(i) + "/species/" + std::to_string(j) + ": \"" + stem.species[j] +
                                   "\" is not among the materials");
            }
        }
        // The stem's length above the kenzan plus what the pins hold must come out of one material.
        double available = 0.0;
        for (const auto& [species, length] : longest_m) {
            if (stem.species.empty() || std::find(stem.species.begin(), stem.species.end(), species) != stem.species.end()) {
                available = std::max(available, length);
            }
        }
        const double wanted = nominal_length_m(*lesson, i) + 0.013;
        if (lesson->scoring == "form" && !longest_m.empty() && available < wanted) {
            char what[200];
            std::snprintf(what, sizeof what, ": /main_stems/%zu: %s wants %.0f mm above the kenzan (and 13 mm in its pins) but its longest material is %.0f mm",
                          i, stem.role.c_str(), nominal_length_m(*lesson, i) * 1e3, available * 1e3);
            problems.push_back(label + what);
        }
    }
    const auto kenzan = load_kenzan(lesson->kenzan_layout);
    if (!kenzan) {
        problems.push_back(label + ": /kenzan/layout: " + kenzan.error().message);
    } else if (lesson->scoring == "form") {
        const glm::dvec2 half_kenzan{0.5 * (kenzan->columns + 1) * kenzan->pitch_m, 0.5 * (kenzan->rows + 1) * kenzan->pitch_m};
        const glm::dvec2 half_box{0.5 * lesson->container.width_m, 0.5 * lesson->container.front_to_back_m};
        const glm::dvec2 reach = glm::abs(lesson->kenzan_offset_m) + half_kenzan;
        const bool fits = lesson->container.shape == ContainerShape::round || lesson->container.shape == ContainerShape::vase
                              ? glm::length(reach) <= half_box.x
                              : reach.x <= half_box.x && reach.y <= half_box.y;
        if (!fits) {
            char what[200];
            std::snprintf(what, sizeof what, ": /kenzan: the %.0f x %.0f mm kenzan at [%.0f, %.0f] mm does not fit inside the container", 2e3 * half_kenzan.x,
                          2e3 * half_kenzan.y, lesson->kenzan_offset_m.x * 1e3, lesson->kenzan_offset_m.y * 1e3);
            problems.push_back(label + what);
        }
    }
    if (lesson->scoring == "sample") {
        const auto file = named_from(lesson->file, lesson->scene);
        const auto scene = file ? load_scene(*file) : Result<SceneDef>(file.error());
        if (!scene) problems.push_back(label + ": /scene: " + scene.error().message);
        else if (scene->sample.empty()) problems.push_back(label + ": /scene: " + lesson->scene + " has no sample to copy");
    }
    if (!problems.empty()) {
        std::string message;
        for (const auto& p : problems) message += (message.empty() ? "" : "\n") + p;
        return make_error(ErrorCode::parse_error, message);
    }
    return lesson;
}

Result<LessonDef> load_lesson(const std::string& id_or_path) {
    if (id_or_path.find('/') != std::string::npos || id_or_path.ends_with(".json")) return load_lesson_file(id_or_path);
    if (!plain_id(id_or_path)) return make_error(ErrorCode::not_found, "no lesson \"" + id_or_path + "\" (see `ikebana lesson list`)");
    const auto path = asset_dir() / "lessons" / (id_or_path + ".json");
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return make_error(ErrorCode::not_found, "no lesson \"" + id_or_path + "\" (see `ikebana lesson list`)");
    return load_lesson_file(path);
}

Result<std::vector<LessonDef>> load_shipped_lessons() {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(asset_dir() / "lessons", ec)) {
        if (entry.path().extension() == ".json") files.push_back(entry.path());
    }
    if (ec) return make_error(ErrorCode::io_error, (asset_dir() / "lessons").string() + ": " + ec.message());
    std::sort(files.begin(), files.end());
    std::vector<LessonDef> out;
    for (const auto& f : files) {
        auto l = load_lesson_file(f);
        if (!l) return std::move(l).error();
        out.push_back(std::move(l).value());
    }
    return out;
}

std::string direction_words(double azimuth_rad) {
    // Eight sectors of 45 degrees, 0 toward the viewer, + to the viewer's left.
    static const char* names[] = {"front", "left front", "left", "left back", "back", "right back", "right", "right front"};
    double a = std::fmod(azimuth_rad / deg, 360.0);
    if (a < 0) a += 360.0;
    return names[static_cast<int>(std::floor((a + 22.5) / 45.0)) % 8];
}

std::string region_words(KenzanRegion r) {
    switch (r) {
    case KenzanRegion::any: return "anywhere on the kenzan";
    case KenzanRegion::centre: return "the centre";
    case KenzanRegion::front: return "the front";
    case KenzanRegion::back: return "the back";
    case KenzanRegion::left: return "the left";
    case KenzanRegion::right: return "the right";
    case KenzanRegion::front_left: return "the front left";
    case KenzanRegion::front_right: return "the front right";
    case KenzanRegion::back_left: return "the back left";
    case KenzanRegion::back_right: return "the back right";
    }
    return "?";
}

std::string rule_name(RuleKind kind) { return rule_names.at(static_cast<std::size_t>(kind)); }

double distance_to_wall_m(bool round, glm::dvec2 half_extent, glm::dvec2 from, glm::dvec2 way) {
    if (round) {
        const double r = half_extent.x;
        const double along = glm::dot(from, way);
        return -along + std::sqrt(std::max(0.0, along * along - (glm::dot(from, from) - r * r)));
    }
    double to_wall = 1e9;
    for (int axis = 0; axis < 2; ++axis) {
        if (std::abs(way[axis]) > 1e-9) to_wall = std::min(to_wall, (std::copysign(half_extent[axis], way[axis]) - from[axis]) / way[axis]);
    }
    return to_wall;
}

glm::dvec3 lesson_direction(double tilt_rad, double azimuth_rad) {
    // The viewer sits at -y looking toward +y: front is -y, the viewer's left is -x.
    return {-std::sin(tilt_rad) * std::sin(azimuth_rad), -std::sin(tilt_rad) * std::cos(azimuth_rad), std::cos(tilt_rad)};
}

void order_for_newcomers(std::vector<LessonDef>& lessons) {
    std::stable_sort(lessons.begin(), lessons.end(), [](const LessonDef& a, const LessonDef& b) {
        const bool form_a = a.scoring == "form", form_b = b.scoring == "form";
        if (form_a != form_b) return form_a;
        return a.level < b.level;
    });
}

} // namespace ikebana::game
