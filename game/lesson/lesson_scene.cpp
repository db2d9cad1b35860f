#include "game/lesson/lesson_scene.hpp"

#include <algorithm>
#include <cmath>

#include "game/asset_paths.hpp"
#include "game/kenzan/kenzan_layout.hpp"
#include "game/species/species.hpp"

namespace ikebana::game {

namespace {
constexpr double wall_m = 0.006; // as World builds containers
}

Result<KenzanFootprint> footprint_of(const LessonDef& l) {
    auto k = load_kenzan(l.kenzan_layout);
    if (!k) return std::move(k).error();
    return KenzanFootprint{{(k->columns + 1) * k->pitch_m, (k->rows + 1) * k->pitch_m}, k->base_thickness_m};
}

Result<SceneDef> scene_for_lesson(const LessonDef& l) {
    if (l.scoring == "sample") return load_scene(asset_path(l.scene));
    const auto kenzan = load_kenzan(l.kenzan_layout);
    if (!kenzan) return std::move(kenzan).error();
    SceneDef s{};
    s.file = l.file;
    s.seed = 1;
    s.gravity_m_s2 = {0, 0, -9.80665};
    s.table_height_m = 0.0;
    s.container = l.container;
    // The kenzan at the origin (where the camera looks), the container around it.
    s.container_centre_m = -l.kenzan_offset_m;
    const double rim = wall_m + l.container.depth_m;
    const double floor = l.container.shape == ContainerShape::vase ? rim - 0.03 : wall_m;
    s.kenzan_layout = l.kenzan_layout;
    s.kenzan_position_m = {0.0, 0.0, floor + kenzan->base_thickness_m};
    // The materials lie across the table in front of the container, longest at the back.
    std::vector<std::pair<double, FlowerPlacement>> lying;
    for (const auto& m : l.materials) {
        const auto species = load_species(m.species);
        if (!species) return std::move(species).error();
        const double length = m.length_m > 0.0 ? m.length_m : species->length_m;
        for (std::uint32_t i = 0; i < m.count; ++i) lying.push_back({length, FlowerPlacement{m.species, Placement::lying, {}, {1, 0, 0}, 0.0, length}});
    }
    std::stable_sort(lying.begin(), lying.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    const double front = s.container_centre_m.y - 0.5 * l.container.front_to_back_m - wall_m;
    double y = front - 0.04;
    for (auto& [length, placement] : lying) {
        placement.base_m = {-0.5 * length, y, 0.0};
        s.flowers.push_back(placement);
        y -= 0.03;
    }
    // The hands just above the materials' right and left ends.
    s.hands.push_back({0, {-0.15, front - 0.08, 0.08}, 0.02, ""});
    s.hands.push_back({1, {0.15, front - 0.08, 0.08}, 0.02, ""});
    // Far enough back to see the tallest stem and the materials.
    double tallest = 0.0;
    for (std::size_t i = 0; i < l.stems.size(); ++i) tallest = std::max(tallest, nominal_length_m(l, i));
    const double height = std::max(0.3, tallest + rim);
    s.display.camera_target_m = glm::dvec3{0.0, front * 0.5, 0.4 * height};
    s.display.camera_position_m = glm::dvec3{0.0, front - 1.3 * height, 0.9 * height};
    s.display.screen_distance_m = glm::length(*s.display.camera_position_m - *s.display.camera_target_m);
    s.rates_hz = {{"haptic", 1000}, {"position_estimate", 100}, {"position_check", 16}, {"render", 30}};
    return s;
}

Arrangement measure_arrangement(const components::FrameSnapshot& frame) {
    Arrangement a;
    if (!frame.kenzan) return a;
    const auto& k = *frame.kenzan;
    if (frame.container) a.kenzan_offset_m = glm::dvec2(k.origin_m) - frame.container->centre_m;
    std::vector<bool> held(frame.flowers.size(), false);
    for (const auto& h : frame.hands) {
        if (h.held_flower >= 0 && static_cast<std::size_t>(h.held_flower) < held.size()) held[static_cast<std::size_t>(h.held_flower)] = true;
    }
    const double pin_top = k.origin_m.z + k.pin_height_m();
    for (std::size_t i = 0; i < frame.flowers.size(); ++i) {
        const auto& f = frame.flowers[i];
        if (held[i] || (!f.in_kenzan && !f.fallen) || f.points_m.size() < 2) continue;
        const auto& x = f.points_m;
        // Where it enters the pins: its line's crossing of the pins' tops (its bottom if that is above them).
        glm::dvec3 entry = x.front();
        std::size_t from = 1;
        for (std::size_t j = 1; j < x.size(); ++j) {
            if (x[j - 1].z < pin_top && x[j].z >= pin_top) {
                const double t = (pin_top - x[j - 1].z) / (x[j].z - x[j - 1].z);
                entry = x[j - 1] + (x[j] - x[j - 1]) * t;
                from = j;
                break;
            }
        }
        ArrangementStem s;
        s.species = f.species;
        s.base_m = glm::dvec2(entry) - glm::dvec2(k.origin_m);
        double length = glm::length(x[from] - entry);
        for (std::size_t j = from + 1; j < x.size(); ++j) length += glm::length(x[j] - x[j - 1]);
        s.length_m = length;
        const glm::dvec3 chord = x.back() - entry;
        const double c = glm::length(chord);
        s.tilt_rad = c > 0.0 ? std::acos(std::clamp(chord.z / c, -1.0, 1.0)) : 0.0;
        s.azimuth_rad = std::atan2(-chord.x, -chord.y); // 0 toward the viewer (-y), + to the viewer's left (-x)
        s.standing = f.in_kenzan && !f.fallen;
        for (std::size_t j = from; j < x.size(); ++j) s.path_m.push_back(x[j] - glm::dvec3(k.origin_m));
        a.stems.push_back(std::move(s));
    }
    return a;
}

} // namespace ikebana::game
