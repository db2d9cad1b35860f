#include "systems/haptics/hand_input_system.hpp"

#include <algorithm>
#include <cmath>
#include <vector>
#include <cstdio>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

namespace {
// Which side of a container's wall a point is on (the wall's middle), and whether it is low enough
// (below the rim, with a stem's radius of slack) for the wall to be in its way.
bool inside_wall(const Container& c, const glm::dvec3& p) { return c.holds_xy(glm::dvec2(p), 0.5 * c.wall_m); }
// Whether moving a held stem by `by` would take one of its points through the container's wall below
// the rim (a trainee's willow went into the kenzan straight through the suiban's front wall, and a
// chrysanthemum ended up under it: the hand's grip moves the stem whatever is in the way).
bool through_wall(const Container& c, const std::vector<glm::dvec3>& x, double radius_m, const glm::dvec3& by) {
    for (const auto& p : x) {
        const glm::dvec3 q = p + by;
        if (std::min(p.z, q.z) >= c.rim_z_m + radius_m || std::max(p.z, q.z) < c.base_z_m) continue;
        if (inside_wall(c, p) != inside_wall(c, q)) return true;
    }
    return false;
}

// Within the plate's outline (a pitch beyond the outer pins, as the cube's own stop above).
bool on_kenzan_plate(const Kenzan& k, const glm::dvec3& p) {
    const glm::dvec3 lo = k.pin_base(0, 0) - glm::dvec3{k.pitch_m};
    const glm::dvec3 hi = k.pin_base(k.columns - 1, k.rows - 1) + glm::dvec3{k.pitch_m};
    return p.x > lo.x && p.x < hi.x && p.y > lo.y && p.y < hi.y;
}
} // namespace

void HandInputSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    auto* devices = r.resource<HandDevices>();
    if (!devices) return;
    const auto* table = r.resource<const Table>();
    const Kenzan* kenzan = r.single<const Kenzan>();
    const Container* container = r.single<const Container>();
    r.view<const HandCube, const WorkspaceMapping, HandInput, HandProxy, Collider>().each(
        [&](ecs::Entity e, const HandCube& cube, const WorkspaceMapping& map, HandInput& input, HandProxy& proxy, Collider& collider) {
            devices::HapticDevice* device = devices->device(cube.hand);
            if (!device) return;
            const auto sample = device->poll(ctx.time_us);
            // Said at each change (and a device away from the first tick), hands start disconnected.
            const auto note = [&](const char* what) {
                if (!devices->events()) return;
                char line[64];
                const int n = std::snprintf(line, sizeof line, "%lld,%s,%u,0\n", static_cast<long long>(ctx.time_us), what, static_cast<unsigned>(cube.hand));
                (void)devices->events()->write(std::string_view(line, static_cast<std::size_t>(n)));
            };
            auto* links = r.resource<HandLinks>();
            if (!sample) {
                if (input.connected || ctx.firing == 0) note("gone");
                if (input.connected) ++input.disconnects;
                input.connected = false;
                if (links && cube.hand < 2) {
                    // Silent or lost, the device is still there: say why the hand let go.
                    const auto code = sample.error().code;
                    links->link[cube.hand] = code == ErrorCode::device_silent ? DeviceLink::silent
                                             : code == ErrorCode::device_lost ? DeviceLink::lost
                                             : input.disconnects > 0         ? DeviceLink::unplugged
                                                                             : DeviceLink::not_answering;
                }
                return;
            }
            if (!input.connected && ctx.firing > 0) note("back");
            input.connected = true;
            if (links && cube.hand < 2) links->link[cube.hand] = DeviceLink::answering;
            if (auto* recorder = devices->recorder(cube.hand)) recorder->record(*sample);
            const double c = std::cos(map.yaw_rad);
            const double s = std::sin(map.yaw_rad);
            auto turn = [&](glm::dvec3 v) { return glm::dvec3{c * v.x - s * v.y, s * v.x + c * v.y, v.z}; };
            const glm::dvec3 previous_device = input.device_m;
            if (device->capabilities().reports_position) {
                input.device_m = map.centre_m + turn(map.scale * sample->position);
                input.rotation_rad = sample->rotation;
            } else {
                input.device_m += turn(sample->position * map.rate_speed_m_s * ctx.dt_s);
                // A cap at rest reads a few hundredths off zero: below the dead zone it does not turn the
                // hand, which would otherwise creep round while nobody touches it.
                const glm::dvec3 twist = glm::mix(glm::dvec3{0.0}, sample->rotation, glm::greaterThan(glm::abs(sample->rotation), glm::dvec3{rate_dead_zone}));
                input.rotation_rad = glm::clamp(input.rotation_rad + twist * map.rate_turn_rad_s * ctx.dt_s, glm::dvec3{-2.0 * M_PI}, glm::dvec3{2.0 * M_PI});
            }
            input.previous_buttons = input.buttons;
            input.buttons = sample->buttons;
            // The proxy: the device position, kept above the table and out of the kenzan's base.
            glm::dvec3 at = input.device_m;
            const double half = 0.5 * cube.edge_m;
            if (table) at.z = std::max(at.z, table->height_m + half);
            if (kenzan) {
                const glm::dvec3 lo = kenzan->pin_base(0, 0) - glm::dvec3{kenzan->pitch_m};
                const glm::dvec3 hi = kenzan->pin_base(kenzan->columns - 1, kenzan->rows - 1) + glm::dvec3{kenzan->pitch_m};
                if (at.x > lo.x - half && at.x < hi.x + half && at.y > lo.y - half && at.y < hi.y + half) {
                    at.z = std::max(at.z, kenzan->origin_m.z + half);
                }
            }
            // A held stem whose end stands on the kenzan's plate (or the table) stops the hand from going
            // lower: pushed on, the hand bent the stem against the plate between its grip and its end
            // (a trainee's cherry branch, let go, kept a segment stretched to twice its length and sank
            // from 51 to 73 degrees). The gap to the device is felt as the plate pushing back.
            if (const auto* grip = r.try_get<const HandGrip>(e); grip && !grip->held.is_null() && at.z < proxy.position_m.z) {
                const auto* stem = r.try_get<const StemPoints>(grip->held);
                const auto* rest = r.try_get<const StemRestShape>(grip->held);
                if (stem && rest && stem->position_m.size() >= 2) {
                    const glm::dvec3 end = stem->position_m.front();
                    const glm::dvec3 axis = glm::normalize(stem->position_m[1] - end);
                    const double end_drop = 0.5 * rest->diameter_m * std::sqrt(std::max(0.0, 1.0 - axis.z * axis.z));
                    double floor = table ? table->height_m : -1e9;
                    if (kenzan && on_kenzan_plate(*kenzan, end)) floor = std::max(floor, kenzan->origin_m.z);
                    if (end.z - end_drop <= floor + end_on_floor_m) at.z = proxy.position_m.z;
                }
            }
            // Nor through the container's wall: a held stem that would cross it below the rim stays on its
            // side (up and down it may still go, so it can be lifted over the rim). The gap to the device
            // is felt as the wall pushing back.
            if (const auto* grip = r.try_get<const HandGrip>(e); grip && !grip->held.is_null() && container) {
                const auto* stem = r.try_get<const StemPoints>(grip->held);
                const auto* rest = r.try_get<const StemRestShape>(grip->held);
                if (stem && rest) {
                    const double radius = 0.5 * rest->diameter_m;
                    if (through_wall(*container, stem->position_m, radius, at - proxy.position_m)) {
                        const glm::dvec3 up_down{proxy.position_m.x, proxy.position_m.y, at.z};
                        at = through_wall(*container, stem->position_m, radius, up_down - proxy.position_m) ? proxy.position_m : up_down;
                    }
                }
            }
            // No faster than a hand: the proxy closes a bigger jump over several ticks.
            if (const auto* grip = r.try_get<const HandGrip>(e); grip && !grip->held.is_null()) {
                const glm::dvec3 step = at - proxy.position_m;
                const double reach = max_hand_speed_m_s * ctx.dt_s;
                if (glm::length(step) > reach) at = proxy.position_m + step * (reach / glm::length(step));
            }
            const glm::dvec3 slip = at - input.device_m;
            proxy.slip_m_s = ctx.dt_s > 0.0 ? (slip - (proxy.position_m - previous_device)) / ctx.dt_s : glm::dvec3{0.0};
            proxy.position_m = at;
            collider.a_m = at;
            collider.b_m = at;
        });
}

} // namespace ikebana::systems
