#include "game/world/species_mechanics.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <system_error>

#include "engine/devices/scripted_device.hpp"
#include "engine/sched/clocks.hpp"
#include "game/species/species.hpp"
#include "game/world/world.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::game {

namespace {

constexpr double pi = 3.14159265358979323846;

// A kenzan on the table and nothing else: the default scene's, without its flowers and hands.
SceneDef bare_scene(const std::filesystem::path& species_file) {
    SceneDef s{};
    s.file = species_file; // the species path below is beside it
    s.seed = 1;
    s.gravity_m_s2 = {0, 0, -9.80665};
    s.kenzan_layout = "standard";
    s.kenzan_position_m = {0, 0, 0.008};
    s.display.stereo = "mono";
    return s;
}

// Runs the scene for `seconds` (with a device for the right hand when given) and returns its last frame.
Result<components::FrameSnapshot> run(const SceneDef& scene, double seconds, std::unique_ptr<devices::HapticDevice> right) {
    auto world = World::create(scene);
    if (!world) return std::move(world).error();
    World& w = **world;
    if (right) w.attach_device(1, std::move(right));
    sched::DeterministicClock clock(w.schedule);
    clock.run_for_us(static_cast<std::int64_t>(seconds * 1e6));
    return w.main.resource<const systems::ReceivedFrames>()->latest();
}

double tilt_deg(const std::vector<glm::dvec3>& x) {
    if (x.size() < 2) return 0.0;
    const glm::dvec3 d = x.back() - x.front();
    const double length = glm::length(d);
    return length > 0.0 ? std::acos(std::clamp(d.z / length, -1.0, 1.0)) * 180.0 / pi : 0.0;
}

} // namespace

Result<SpeciesMechanics> species_mechanics(const std::filesystem::path& species_file, double settle_s) {
    auto species = load_species_file(species_file);
    if (!species) return std::move(species).error();
    SpeciesMechanics out;
    out.id = species->id;
    out.length_mm = species->length_m * 1e3;
    // The trial scenes name the file by its whole path (a name without ".json" would be taken for an id).
    std::error_code ec;
    const auto whole = std::filesystem::absolute(species_file, ec);
    const std::string named = (ec ? species_file : whole).string();
    for (const double set_at : {0.0, 45.0, 70.0}) {
        SceneDef scene = bare_scene(species_file);
        const double a = set_at * pi / 180.0;
        // Pushed 13 mm into the pins (the default scene's sunflower), leaning toward the viewer's right.
        scene.flowers.push_back({named, Placement::inserted, {0.0, 0.0, 0.010}, {std::sin(a), 0.0, std::cos(a)}, 0.013});
        auto last = run(scene, settle_s, nullptr);
        if (!last) return std::move(last).error();
        if (last->flowers.empty()) return make_error(ErrorCode::invalid_argument, named + ": the trial's flower is missing");
        const auto& f = last->flowers.front();
        StandTrial t;
        t.set_at_deg = set_at;
        t.stands = f.in_kenzan && !f.fallen;
        t.reason = f.fallen ? components::fall_words(f.fall_reason) : (f.in_kenzan ? "" : "it came out of the pins");
        t.tilt_deg = tilt_deg(f.points_m);
        t.holding_nm = f.holding_moment_nm;
        t.gravity_nm = f.gravity_moment_nm;
        out.stands.push_back(t);
        out.scenes.push_back({scene, *last});
    }
    {
        // Held by its base, level, a hand's height above the table: the right hand takes the bottom
        // point in the first tick and keeps it (and the stem's first segment's direction) still.
        SceneDef scene = bare_scene(species_file);
        const glm::dvec3 base{-0.5 * species->length_m, 0.0, 0.30};
        scene.kenzan_position_m = {0.0, 0.25, 0.008}; // out of the way, behind
        scene.flowers.push_back({named, Placement::lying, base, {1.0, 0.0, 0.0}, 0.0});
        scene.hands.push_back({1, base, 0.02, ""});
        std::ostringstream csv;
        csv << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n0," << base.x << "," << base.y << "," << base.z << ",0,0,0,1\n"
            << settle_s + 1.0 << "," << base.x << "," << base.y << "," << base.z << ",0,0,0,1\n";
        auto keys = devices::parse_trajectory(csv.str(), "the sag trial's hand");
        if (!keys) return std::move(keys).error();
        auto last = run(scene, settle_s, std::make_unique<devices::ScriptedDevice>(*keys, devices::ScriptedDevice::Mode::interpolate));
        if (!last) return std::move(last).error();
        if (last->flowers.empty()) return make_error(ErrorCode::invalid_argument, named + ": the trial's flower is missing");
        const auto& x = last->flowers.front().points_m;
        const glm::dvec3 d = x.back() - x.front();
        out.sag.tip_drop_mm = (x.front().z - x.back().z) * 1e3;
        out.sag.tip_angle_deg = std::atan2(-d.z, std::hypot(d.x, d.y)) * 180.0 / pi;
        out.scenes.push_back({scene, *last});
    }
    return out;
}

} // namespace ikebana::game
