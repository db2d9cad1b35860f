#include "game/world/sample_arrangement.hpp"

#include <cmath>

#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "game/training/arrangement_score.hpp"
#include "game/world/world.hpp"

namespace ikebana::game {

std::vector<ArrangedStem> arranged_stems(const components::FrameSnapshot& frame) {
    std::vector<ArrangedStem> out;
    for (const auto& f : frame.flowers) {
        if (f.points_m.size() < 2) continue;
        out.push_back({f.species, f.points_m.front(), f.points_m.back(), f.in_kenzan, f.fallen});
    }
    return out;
}

glm::dvec3 kenzan_origin(World& w) {
    const auto* k = w.sim.single<components::Kenzan>();
    return k ? k->origin_m : glm::dvec3{0.0};
}

void add_sample_to_draw_list(render::DrawList& list, World& w, const std::vector<SampleStem>& sample) {
    if (sample.empty()) return;
    const auto* k = w.sim.single<components::Kenzan>();
    if (!k) return;
    const glm::dvec3 origin = k->origin_m + sample_offset_m;
    const double size = (k->columns + 1) * k->pitch_m;
    const glm::mat4 base(glm::vec4(static_cast<float>(size), 0, 0, 0), glm::vec4(0, static_cast<float>((k->rows + 1) * k->pitch_m), 0, 0),
                         glm::vec4(0, 0, static_cast<float>(k->base_thickness_m), 0),
                         glm::vec4(glm::vec3(origin - glm::dvec3{0, 0, 0.5 * k->base_thickness_m}), 1.0f));
    list.batch("cube").instances.push_back({base, {0.3f, 0.3f, 0.33f, 1.0f}});
    for (const auto& s : sample) {
        const auto species = w.species.find(s.species);
        const glm::dvec3 dir{std::sin(s.angle_rad) * std::cos(s.azimuth_rad), std::sin(s.angle_rad) * std::sin(s.azimuth_rad), std::cos(s.angle_rad)};
        const glm::dvec3 from = origin + glm::dvec3(s.base_m, 0.0);
        const double length = dir.z > 1e-6 ? s.height_m / dir.z : s.height_m;
        const glm::dvec3 to = from + dir * length;
        const double radius = species != w.species.end() ? 0.5 * species->second.diameter_m : 0.003;
        const glm::dvec3 a = std::abs(dir.x) < 0.9 ? glm::normalize(glm::cross(dir, glm::dvec3{1, 0, 0})) : glm::normalize(glm::cross(dir, glm::dvec3{0, 1, 0}));
        const glm::dvec3 b = glm::cross(dir, a);
        const glm::mat4 stem(glm::vec4(glm::vec3(a * radius), 0), glm::vec4(glm::vec3(b * radius), 0), glm::vec4(glm::vec3(to - from), 0),
                             glm::vec4(glm::vec3(from), 1));
        const glm::vec3 colour = species != w.species.end() ? species->second.stem_colour : glm::vec3(0.4f);
        list.batch("cylinder").instances.push_back({stem, glm::vec4(colour, 1.0f)});
        if (species != w.species.end() && !species->second.head_mesh.empty()) {
            const glm::mat4 head(glm::vec4(glm::vec3(a), 0), glm::vec4(glm::vec3(b), 0), glm::vec4(glm::vec3(dir), 0), glm::vec4(glm::vec3(to), 1));
            list.batch(species->second.head_mesh).instances.push_back({head, glm::vec4(species->second.head_colour, 1.0f)});
        }
    }
}

} // namespace ikebana::game
