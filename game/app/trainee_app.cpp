#include "game/app/trainee_app.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include <GLFW/glfw3.h>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "engine/devices/mouse_keyboard_device.hpp"
#include "engine/platform/pointer_input.hpp"
#include "engine/platform/window.hpp"
#include "engine/render/stereo_renderer.hpp"
#include "engine/render/swapchain.hpp"
#include "engine/sched/clocks.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/render_command.hpp"
#include "game/app/hud.hpp"
#include "game/training/arrangement_score.hpp"
#include "game/training/sample_arrangement.hpp"
#include "game/devices/hand_device_selection.hpp"
#include "game/scene/scene.hpp"
#include "game/world/world.hpp"
#include "systems/presentation/draw_list_system.hpp"

namespace ikebana::game {

namespace {

// The window has no room for a heads-up display yet: its title carries the state.
std::string status_line(World& w) {
    std::string s = "Ikebana";
    std::size_t i = 0;
    w.sim.view<components::InsertionHistory, components::KenzanGrip>().each(
        [&](ecs::Entity, components::InsertionHistory& h, components::KenzanGrip& grip) {
            char part[96];
            std::snprintf(part, sizeof part, " | %s: %u insertions%s%s", i < w.flowers.size() ? w.flowers[i].species.c_str() : "flower",
                          h.insertions_total, h.bottom_broken ? ", split" : "", grip.fallen ? ", fell" : "");
            s += part;
            ++i;
        });
    return s;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)))];
}

int offscreen_instead(const TraineeAppOptions& o, const std::string& why) {
    const auto out = (std::filesystem::temp_directory_path() / "ikebana-frames").string();
    std::printf("ikebana: %s; rendering the scene offscreen instead\n", why.c_str());
    RenderOptions r;
    r.scene = o.scene;
    r.frames = o.frames > 0 ? o.frames : 30;
    r.stereo = o.stereo;
    r.out = out;
    r.width = o.stereo == "sbs" ? std::max(16u, o.width / 2) : o.width;
    r.height = o.height;
    r.validation = o.validation;
    const int code = run_render(r);
    if (code == 0) std::printf("ikebana: the images are in %s\n", out.c_str());
    return code;
}

} // namespace

int run_trainee_app(const TraineeAppOptions& o) {
    auto scene = load_scene(o.scene);
    if (!scene) {
        std::cerr << "ikebana: " << scene.error().message << "\n";
        return 2;
    }
    if (auto env = apply_environment_overrides(scene->environment, o.env); !env) {
        std::cerr << "ikebana: " << env.error().message << "\n";
        return 2;
    }
    // Devices first: what the trainee holds decides how the hands move.
    std::array<std::unique_ptr<devices::HapticDevice>, 2> picked;
    HudInfo hud;
    const std::string* specs[2] = {&o.left_device, &o.right_device};
    for (std::uint8_t hand = 0; hand < 2; ++hand) {
        auto opened = open_hand_device(*specs[hand], hand);
        if (!opened) {
            std::cerr << "ikebana: " << (hand ? "--right: " : "--left: ") << opened.error().message << "\n";
            return 2;
        }
        std::printf("%s hand: %s%s\n", hand ? "right" : "left", opened->description.c_str(), opened->device ? "" : " (mouse and keyboard in the window)");
        picked[hand] = std::move(opened->device);
        hud.device[hand] = picked[hand] ? opened->description : "mouse and keyboard";
    }
    const std::string stereo = o.stereo.empty() ? scene->display.stereo : o.stereo;
    auto window = platform::Window::create("Ikebana", o.width, o.height);
    if (!window) {
        TraineeAppOptions fallback = o;
        fallback.stereo = stereo;
        return offscreen_instead(fallback, window.error().message);
    }

    auto render_mode = render::parse_stereo_mode(stereo);
    if (!render_mode) {
        std::cerr << "ikebana: " << render_mode.error().message << "\n";
        return 2;
    }
    auto ctx = render::VulkanContext::create(
        {.validation = o.validation, .require_validation = false, .instance_extensions = platform::Window::required_instance_extensions()});
    if (!ctx) {
        std::cerr << "ikebana: " << ctx.error().message << "\n";
        return 3;
    }
    auto surface = (*window)->create_surface((*ctx)->instance());
    if (!surface) {
        std::cerr << "ikebana: " << surface.error().message << "\n";
        return 3;
    }
    struct SurfaceGuard {
        VkInstance instance;
        VkSurfaceKHR surface;
        ~SurfaceGuard() { vkDestroySurfaceKHR(instance, surface, nullptr); }
    };
    int code = 0;
    {
        // Everything drawn into the surface is gone before the surface itself.
        SurfaceGuard guard{(*ctx)->instance(), *surface};
        auto swapchain = render::Swapchain::create(**ctx, *surface, (*window)->framebuffer());
        if (!swapchain) {
            std::cerr << "ikebana: " << swapchain.error().message << "\n";
            return 3;
        }
        render::RendererOptions ro;
        ro.mode = *render_mode;
        ro.asset_dir = asset_dir();
        ro.eye_width = std::max(1u, *render_mode == render::StereoMode::side_by_side ? o.width / 2 : o.width);
        ro.eye_height = std::max(1u, o.height);
        auto renderer = render::StereoRenderer::create(**ctx, ro);
        if (!renderer) {
            std::cerr << "ikebana: " << renderer.error().message << "\n";
            return 3;
        }
        auto world = World::create(*scene);
        if (!world) {
            std::cerr << "ikebana: " << world.error().message << "\n";
            return 2;
        }
        World& w = **world;
        platform::GlfwPointerSource window_pointer((*window)->glfw());
        devices::MouseKeyboardHands mouse(o.pointer ? *o.pointer : static_cast<platform::PointerSource&>(window_pointer));
        for (std::uint8_t hand = 0; hand < 2; ++hand) w.attach_device(hand, picked[hand] ? std::move(picked[hand]) : mouse.hand(hand));
        std::printf("ikebana: %s on %s (%s); arrows or right-drag orbit the camera, Tab switches hands, Esc ends\n",
                    render::stereo_mode_name(*render_mode), (*ctx)->device_name().c_str(), (*renderer)->multiview() ? "multiview" : "one pass per eye");

        // The simulation keeps wall-clock time on a fixed timeline; a slow frame is caught up at most
        // 0.1 s at once (the rest is dropped, never run as one big step).
        sched::DeterministicClock clock(w.schedule);
        const double render_hz = w.schedule.rates().hz("render");
        render::StereoRig base_rig;
        base_rig.eye_separation_m = scene->display.eye_separation_m;
        base_rig.screen_distance_m = scene->display.screen_distance_m;
        base_rig.vertical_fov_rad = scene->display.vertical_fov_rad;
        double yaw = 0.0, pitch = 0.0;
        auto last = std::chrono::steady_clock::now();
        std::pair<double, double> drag_from{0.0, 0.0};
        bool dragging = false;
        std::uint32_t presented = 0;
        bool enter_was_down = false;
        std::vector<double> frame_ms, record_ms, shadow_ms, eyes_ms, composite_ms, present_ms;
        auto previous_frame = std::chrono::steady_clock::now();
        std::optional<ArrangementScore> last_result;
        std::optional<render::RgbaImage> last_shot;
        while (!(*window)->should_close()) {
            if (o.each_frame) o.each_frame(presented, (*window)->glfw());
            (*window)->poll_events();
            if ((*window)->key_down(GLFW_KEY_ESCAPE)) (*window)->request_close();
            const auto now = std::chrono::steady_clock::now();
            const double dt = std::min(0.1, std::chrono::duration<double>(now - last).count());
            last = now;
            // Camera: during training, not only after it (the paper's future work).
            const double turn = 1.2 * dt;
            if ((*window)->key_down(GLFW_KEY_LEFT)) yaw -= turn;
            if ((*window)->key_down(GLFW_KEY_RIGHT)) yaw += turn;
            if ((*window)->key_down(GLFW_KEY_UP)) pitch += turn;
            if ((*window)->key_down(GLFW_KEY_DOWN)) pitch -= turn;
            const auto cursor = (*window)->cursor();
            if ((*window)->mouse_down(GLFW_MOUSE_BUTTON_RIGHT)) {
                if (dragging) {
                    yaw += 0.005 * (cursor.first - drag_from.first);
                    pitch += 0.005 * (cursor.second - drag_from.second);
                }
                dragging = true;
                drag_from = cursor;
            } else {
                dragging = false;
            }
            pitch = std::clamp(pitch, -0.5, 1.0);
            // "Forward" on the device stays "away from the viewer".
            w.sim.view<components::WorkspaceMapping>().each([&](ecs::Entity, components::WorkspaceMapping& m) { m.yaw_rad = yaw; });
            clock.run_for_us(static_cast<std::int64_t>(dt * 1e6));

            const VkExtent2D size = (*window)->framebuffer();
            if (size.width == 0 || size.height == 0) {
                (*window)->wait_events(); // minimised: nothing to draw
                continue;
            }
            if (size.width != (*swapchain)->extent().width || size.height != (*swapchain)->extent().height) {
                if (auto r = (*swapchain)->recreate(size); !r) {
                    std::cerr << "ikebana: " << r.error().message << "\n";
                    code = 3;
                    break;
                }
            }
            // Enter: the trainee is done; the result stays on screen and the session goes on.
            const bool enter = (*window)->key_down(GLFW_KEY_ENTER) || (*window)->key_down(GLFW_KEY_KP_ENTER);
            if ((enter && !enter_was_down) || (o.finish_at_frame > 0 && presented + 1 == o.finish_at_frame)) {
                const auto result = score_arrangement(arranged_stems(w), scene->sample, kenzan_origin(w));
                hud.result = scene->sample.empty() ? std::vector<std::string>{"RESULT: free practice (this scene has no sample)"} : result.lines();
                for (const auto& line : hud.result) std::printf("%s\n", line.c_str());
                last_result = result;
            }
            enter_was_down = enter;
            const auto* list = w.sim.resource<render::DrawList>();
            render::DrawList drawn = list ? *list : systems::build_draw_list(w.sim);
            add_sample_to_draw_list(drawn, w, scene->sample);
            hud.time_s = static_cast<double>(clock.now_us()) * 1e-6;
            (*renderer)->set_overlay(hud_panels(w, hud));
            const bool want_shot = !o.screenshot.empty() && o.frames > 0 && presented + 1 >= o.frames;
            auto frame = (*renderer)->present(**swapchain, drawn, render::orbited(base_rig, yaw, pitch), want_shot);
            if (!frame) {
                std::cerr << "ikebana: " << frame.error().message << "\n";
                code = 3;
                break;
            }
            for (const auto& warning : (*renderer)->take_warnings()) std::cerr << "ikebana: warning: " << warning << "\n";
            if (frame->swapchain_stale) {
                if (auto r = (*swapchain)->recreate((*window)->framebuffer()); !r && (*window)->framebuffer().width > 0) {
                    std::cerr << "ikebana: " << r.error().message << "\n";
                    code = 3;
                    break;
                }
            }
            if (!frame->presented) continue;
            ++presented;
            const auto frame_end = std::chrono::steady_clock::now();
            frame_ms.push_back(std::chrono::duration<double, std::milli>(frame_end - previous_frame).count());
            previous_frame = frame_end;
            record_ms.push_back(frame->timing.record_ms);
            shadow_ms.push_back(frame->timing.shadow_ms);
            eyes_ms.push_back(frame->timing.scene_ms);
            composite_ms.push_back(frame->timing.composite_ms);
            present_ms.push_back(frame->timing.present_ms);
            if (frame->screenshot) last_shot = std::move(frame->screenshot);
            if (presented % 15 == 0) glfwSetWindowTitle((*window)->glfw(), status_line(w).c_str());
            if (o.frames > 0 && presented >= o.frames) break;
            // Frames at the scheduler's render rate (30 Hz by default), not as fast as presenting allows.
            const auto period = std::chrono::duration<double>(1.0 / render_hz);
            const auto spent = std::chrono::steady_clock::now() - now;
            if (spent < period) std::this_thread::sleep_for(period - spent);
        }
        if (!o.screenshot.empty()) {
            if (!last_shot) {
                std::cerr << "ikebana: no screenshot: the window's images cannot be copied from on this device\n";
                code = code ? code : 1;
            } else if (auto wr = render::write_png(o.screenshot, *last_shot); !wr) {
                std::cerr << "ikebana: " << wr.error().message << "\n";
                code = code ? code : 1;
            } else {
                std::printf("ikebana: screenshot in %s\n", o.screenshot.c_str());
            }
        }
        std::printf("ikebana: %u frames presented; %s\n", presented, status_line(w).c_str());
        if (frame_ms.size() > 2) {
            frame_ms.erase(frame_ms.begin()); // the first frame includes start-up
            std::printf("frame time, ms (p50 / p95): whole frame %.1f / %.1f; record %.2f / %.2f; device: shadow %.1f / %.1f, both eyes %.1f / %.1f, "
                        "composite and HUD %.1f / %.1f; present %.2f / %.2f\n",
                        percentile(frame_ms, 0.5), percentile(frame_ms, 0.95), percentile(record_ms, 0.5), percentile(record_ms, 0.95),
                        percentile(shadow_ms, 0.5), percentile(shadow_ms, 0.95), percentile(eyes_ms, 0.5), percentile(eyes_ms, 0.95),
                        percentile(composite_ms, 0.5), percentile(composite_ms, 0.95), percentile(present_ms, 0.5), percentile(present_ms, 0.95));
        }
        if ((*ctx)->validation_enabled()) {
            std::printf("validation: %u errors, %u warnings\n", (*ctx)->validation_errors(), (*ctx)->validation_warnings());
            if ((*ctx)->validation_errors() > 0 && code == 0) code = 4;
        }
        vkDeviceWaitIdle((*ctx)->device());
    }
    return code;
}

} // namespace ikebana::game
