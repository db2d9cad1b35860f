#include "systems/haptics/bending_system.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include "engine/ecs/registry.hpp"
#include "systems/haptics/bending.hpp"

namespace ikebana::systems {

using namespace components;

void BendingSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    struct Hand {
        const HandInput* input;
        const HandProxy* proxy;
        const HandGrip* grip;
    };
    std::optional<Hand> hands[2];
    r.view<const HandCube, const HandInput, const HandProxy, const HandGrip>().each(
        [&](ecs::Entity, const HandCube& cube, const HandInput& input, const HandProxy& proxy, const HandGrip& grip) {
            if (cube.hand < 2) hands[cube.hand] = Hand{&input, &proxy, &grip};
        });
    // A bend that stops hands its points back to the physics (except the ones a hand holds).
    r.view<Bending, StemPoints>().each([&](ecs::Entity flower, Bending& b, StemPoints& pts) {
        if (b.active) {
            for (std::uint32_t i = b.support_a; i <= b.support_b && i < pts.pinned.size(); ++i) {
                auto holds = [&](const std::optional<Hand>& h) {
                    return h && h->grip->held == flower && (h->grip->held_point == i || (h->grip->holds_direction && h->grip->second_point == i));
                };
                const bool held = holds(hands[0]) || holds(hands[1]);
                if (!held) pts.pinned[i] = 0;
            }
        }
        b.active = false;
        b.force_n = 0.0;
    });
    if (!hands[0] || !hands[1]) {
        r.view<Bending>().each([](ecs::Entity, Bending& b) { b.hands_together = false; });
        return;
    }
    const Hand& left = *hands[0];
    const Hand& right = *hands[1];
    const ecs::Entity held = left.grip->held;
    const bool together = !held.is_null() && held == right.grip->held &&
                          glm::length(left.proxy->position_m - right.proxy->position_m) <= tips_together_m;
    // Only the flower both hands hold together is being bent; the others' wrists are apart.
    r.view<Bending>().each([&](ecs::Entity flower, Bending& b) {
        if (!together || flower != held) b.hands_together = false;
    });
    if (!together) return;
    auto* points = r.try_get<StemPoints>(held);
    auto* rest = r.try_get<StemRestShape>(held);
    const auto* springs = r.try_get<const StemSprings>(held);
    auto* bend = r.try_get<Bending>(held);
    if (!points || !rest || !springs || !bend || points->position_m.size() < 3) return;
    const double roll = left.input->rotation_rad.x - right.input->rotation_rad.x;
    if (!bend->hands_together) {
        bend->hands_together = true;
        bend->roll_at_start_rad = roll;
        bend->bent_rad = 0.0;
    }
    // Rolled past half a turn is rolled back the other way (device angles wrap at +-pi).
    const double wanted = std::min(std::abs(std::remainder(roll - bend->roll_at_start_rad, 2.0 * M_PI)), M_PI - 1e-3);
    const double step = max_bend_rad_s * ctx.dt_s;
    bend->bent_rad = std::clamp(wanted, bend->bent_rad - step, bend->bent_rad + step);
    const double theta = M_PI - bend->bent_rad;
    if (M_PI - theta < 1e-3) return;

    // C: the stem point nearest the middle of the two hands; A and B: L/2 of rest length either side.
    auto& x = points->position_m;
    const glm::dvec3 middle = 0.5 * (left.proxy->position_m + right.proxy->position_m);
    std::size_t c = 0;
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (glm::length(x[i] - middle) < nearest) {
            nearest = glm::length(x[i] - middle);
            c = i;
        }
    }
    std::size_t a = c;
    std::size_t b = c;
    for (double run = 0.0; a > 0 && run < 0.5 * span_m; --a) run += rest->segment_length_m[a - 1];
    for (double run = 0.0; b + 1 < x.size() && run < 0.5 * span_m; ++b) run += rest->segment_length_m[b];
    if (b - a < 2) return;
    const glm::dvec3 ab = x[b] - x[a];
    const double span = glm::length(ab);
    if (span <= 0.0) return;
    const glm::dvec3 along = ab / span;
    // The thumbs push upwards (perpendicular to A-B in the vertical plane), or sideways if A-B is vertical.
    glm::dvec3 push = glm::dvec3{0, 0, 1} - glm::dot(glm::dvec3{0, 0, 1}, along) * along;
    if (glm::length(push) < 1e-6) push = glm::dvec3{1, 0, 0} - glm::dot(glm::dvec3{1, 0, 0}, along) * along;
    push = glm::normalize(push);

    // Eq. 4 between the supports: the points are held on the bent shape while the hands bend it.
    double rest_span = 0.0;
    for (std::size_t k = a; k < b; ++k) rest_span += rest->segment_length_m[k];
    const glm::dvec3 origin = x[a];
    double s = 0.0;
    for (std::size_t i = a; i <= b; ++i) {
        if (i > a) s += rest->segment_length_m[i - 1];
        const double along_s = s * span / std::max(rest_span, 1e-12);
        const glm::dvec3 target = origin + along * along_s + push * bending::displacement(along_s, span, theta);
        points->velocity_m_s[i] = ctx.dt_s > 0.0 ? (target - x[i]) / ctx.dt_s : glm::dvec3{0.0};
        x[i] = target;
        points->pinned[i] = 1;
    }
    // Eq. 5, with E I from the hinge springs (k_theta = E I / l).
    const double ei = springs->hinge_nm_per_rad.empty() ? 0.0 : springs->hinge_nm_per_rad[0] * rest->segment_length_m[0];
    bend->active = true;
    bend->theta_rad = theta;
    bend->span_m = span;
    bend->support_a = static_cast<std::uint32_t>(a);
    bend->support_b = static_cast<std::uint32_t>(b);
    bend->push_direction = push;
    bend->force_n = bending::force(ei, span, theta);
    // Permanent set: only what this bend adds beyond what the flower has already taken.
    const double beyond = (M_PI - theta) - bend->permanent_set_rad;
    if (beyond > bend->set_applied_rad && a + 1 <= b - 1) {
        const double add = beyond - bend->set_applied_rad;
        bending::apply_permanent_set(*rest, a, b - 2, M_PI - (bend->permanent_set_rad + add), bend->permanent_set_rad,
                                     r.try_get<const StemFrame>(held), &points->position_m);
        bend->set_applied_rad = beyond;
    }
}

} // namespace ikebana::systems
