#include "engine/core/percentile.hpp"
#include "game/render/offscreen_render.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <vector>

#include <unistd.h>

#include "engine/assets/files.hpp"
#include "engine/render/stereo_renderer.hpp"
#include "engine/sched/clocks.hpp"
#include "game/meshes/procedural_meshes.hpp"
#include "game/asset_paths.hpp"
#include "game/scene/scene.hpp"
#include "game/lesson/lesson.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/world/world.hpp"
#include "components/presentation.hpp"

namespace ikebana::game {

// The offscreen draw: the main lane's last phase, like the window's present, drawing what
// prepare_frame_system prepared (the world, the sample, the HUD) into PNGs.
struct OffscreenDrawSystem {
    static constexpr std::string_view name = "offscreen_draw";
    static constexpr std::string_view lane = "main";
    static constexpr std::string_view phase = "draw";
    static constexpr std::string_view rate = "render";
    using reads = sched::Components<components::PreparedFrame>;
    using writes = sched::Components<>;
    std::function<void(const components::PreparedFrame&)> draw;
    void operator()(sched::SystemContext& ctx) {
        if (const auto* prepared = ctx.registry.resource<const components::PreparedFrame>()) draw(*prepared);
    }
};

render::StereoRig rig_of(const DisplayDef& display) {
    render::StereoRig rig;
    rig.eye_separation_m = display.eye_separation_m;
    rig.screen_distance_m = display.screen_distance_m;
    rig.vertical_fov_rad = display.vertical_fov_rad;
    if (display.camera_position_m) rig.position_m = *display.camera_position_m;
    if (display.camera_target_m) rig.target_m = *display.camera_target_m;
    return rig;
}

int run_render(const RenderOptions& o) {
    // A lesson's scene is the table it sets (its materials laid out, its container and kenzan), seen
    // from where the window's camera starts.
    auto scene = [&]() -> Result<SceneDef> {
        if (o.lesson.empty()) return load_scene(o.scene);
        auto lesson = load_lesson(o.lesson);
        if (!lesson) return std::move(lesson).error();
        return scene_for_lesson(*lesson);
    }();
    if (!scene) {
        std::cerr << "ikebana render: " << scene.error().message << "\n";
        return 2;
    }
    auto mode = render::parse_stereo_mode(o.stereo.empty() ? scene->display.stereo : o.stereo);
    if (!mode) {
        std::cerr << "ikebana render: " << mode.error().message << "\n";
        return 2;
    }
    // The PNGs are written at the end, all or none: a render that fails (a size the device refuses)
    // leaves no empty or half-filled folder behind.
    assets::OutputBatch outputs;
    if (auto folder = outputs.folder(o.out); !folder) {
        std::cerr << "ikebana render: --out: " << folder.error().message << "\n";
        return 2;
    }
    auto ctx = render::VulkanContext::create({.validation = o.validation, .require_validation = false, .instance_extensions = {}});
    if (!ctx) {
        std::cerr << "ikebana render: " << ctx.error().message << "\n";
        return 3;
    }
    render::RendererOptions ro;
    ro.eye_width = o.width;
    ro.eye_height = o.height;
    ro.mode = *mode;
    ro.asset_dir = asset_dir();
    ro.generated_mesh = part_mesh_of_name; // a petal or leaf a species draws without a file
    ro.msaa_samples = o.msaa;
    if (o.full_detail) ro.coarse_below_px = 0.0;
    auto renderer = render::StereoRenderer::create(**ctx, ro);
    if (!renderer) {
        std::cerr << "ikebana render: " << renderer.error().message << "\n";
        return 3;
    }
    render::StereoRig rig = rig_of(scene->display);
    rig = render::orbited(rig, o.yaw_deg * M_PI / 180.0, o.pitch_deg * M_PI / 180.0);
    const bool tty = isatty(fileno(stderr)) != 0;
    std::vector<double> record, execute, readback, shadow, scene_pass, composite, eye_triangles, shadow_triangles;
    std::uint32_t written = 0;
    int code = 0;
    OffscreenDrawSystem offscreen;
    offscreen.draw = [&](const components::PreparedFrame& prepared) {
        if (code != 0 || written >= o.frames) return;
        (*renderer)->set_overlay(prepared.overlay);
        auto frame = (*renderer)->render(prepared.list, rig, true);
        if (!frame) {
            std::cerr << "ikebana render: frame " << written + 1 << ": " << frame.error().message << "\n";
            code = 3;
            return;
        }
        for (const auto& warning : (*renderer)->take_warnings()) std::cerr << "ikebana render: warning: " << warning << "\n";
        ++written;
        record.push_back(frame->timing.record_ms);
        execute.push_back(frame->timing.execute_ms);
        readback.push_back(frame->timing.readback_ms);
        shadow.push_back(frame->timing.shadow_ms);
        scene_pass.push_back(frame->timing.scene_ms);
        composite.push_back(frame->timing.composite_ms);
        eye_triangles.push_back(static_cast<double>(frame->timing.eye_triangles));
        shadow_triangles.push_back(static_cast<double>(frame->timing.shadow_triangles));
        char name[64];
        for (const auto& [suffix, image] : {std::pair{"left", &frame->left}, std::pair{"right", &frame->right}, std::pair{"composed", &frame->composed}}) {
            std::snprintf(name, sizeof name, "frame_%04u_%s.png", written, suffix);
            const auto path = std::filesystem::path(o.out) / name;
            auto png = render::encode_png(*image, path.string());
            auto wr = png ? outputs.add(path, *png) : Result<void>(png.error());
            if (!wr) {
                std::cerr << "ikebana render: " << wr.error().message << "\n";
                code = 1;
                return;
            }
        }
        if (tty && !o.quiet) std::fprintf(stderr, "\r\033[Kframe %u / %u", written, o.frames);
    };
    // The same world, systems and presentation path as the window: only the last phase differs.
    auto world = World::create(*scene, WorldOptions{.rate_overrides = {}, .force_scheme = {}, .main_lane_systems = {sched::describe(offscreen)}});
    if (!world) {
        std::cerr << "ikebana render: " << world.error().message << "\n";
        return 2;
    }
    World& w = **world;
    sched::DeterministicClock clock(w.schedule);
    // One frame at each render firing: the first shows the scene after its first tick.
    const auto step_us = static_cast<std::int64_t>(std::llround(1e6 / w.schedule.rates().hz("render")));
    while (written < o.frames && code == 0) clock.run_for_us(step_us);
    if (tty && !o.quiet) std::fprintf(stderr, "\r\033[K");
    if (code != 0) return code;
    if (auto done = outputs.commit(); !done) {
        std::cerr << "ikebana render: " << done.error().message << "\n";
        return 1;
    }
    const auto out_extent = (*renderer)->output_extent();
    std::printf("rendered %u frame(s) of the scene on %s (%s, %s, %ux%u per eye, %ux anti-aliasing, composed %ux%u) into %s\n", o.frames,
                (*ctx)->device_name().c_str(), render::stereo_mode_name(*mode), (*renderer)->multiview() ? "multiview" : "one pass per eye",
                o.width, o.height, (*renderer)->samples(), out_extent.width, out_extent.height, o.out.c_str());
    std::printf("frame time, ms (p50 / p95): record %.2f / %.2f, device %.2f / %.2f, readback %.2f / %.2f\n", percentile(record, 0.5),
                percentile(record, 0.95), percentile(execute, 0.5), percentile(execute, 0.95), percentile(readback, 0.5), percentile(readback, 0.95));
    std::printf("device time by pass, ms (p50 / p95): shadow %.2f / %.2f, both eyes %.2f / %.2f, composite and HUD %.2f / %.2f\n",
                percentile(shadow, 0.5), percentile(shadow, 0.95), percentile(scene_pass, 0.5), percentile(scene_pass, 0.95),
                percentile(composite, 0.5), percentile(composite, 0.95));
    std::printf("triangles a frame (p50): an eye's pass %.0f, the shadow's %.0f%s\n", percentile(eye_triangles, 0.5), percentile(shadow_triangles, 0.5),
                o.full_detail ? " (every mesh as modelled)" : "");
    if ((*ctx)->validation_enabled()) std::printf("validation: %u errors, %u warnings\n", (*ctx)->validation_errors(), (*ctx)->validation_warnings());
    return (*ctx)->validation_errors() == 0 ? 0 : 4;
}

} // namespace ikebana::game
