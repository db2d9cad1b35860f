#include "game/app/trainee_app.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <atomic>
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
#include "engine/sched/rates.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/render_command.hpp"
#include "game/app/hud.hpp"
#include "game/training/arrangement_score.hpp"
#include "game/training/sample_arrangement.hpp"
#include "game/devices/hand_device_selection.hpp"
#include "game/scene/scene.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"
#include "game/devices/force_watchdogs.hpp"
#include "systems/presentation/receive_frame_system.hpp"
#include "systems/presentation/draw_list_system.hpp"

namespace ikebana::game {

namespace {

// The window's title: the flowers' state, for the task bar.
std::string status_line(const components::FrameSnapshot& frame) {
    std::string s = "Ikebana";
    for (const auto& f : frame.flowers) {
        char part[96];
        std::snprintf(part, sizeof part, " | %s: %u insertions%s%s", f.species.c_str(), f.insertions, f.bottom_broken ? ", split" : "",
                      f.fallen ? ", fell" : "");
        s += part;
    }
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
    // Rates are checked before anything opens, so that a bad one is an error with or without a display.
    for (const auto& assignment : o.rates) {
        sched::RateTable rates = sched::RateTable::paper_defaults();
        if (auto r = rates.set_from_string(assignment); !r) {
            std::cerr << "ikebana: --rate: " << r.error().message << "\n";
            return 2;
        }
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
        // The eyes in the window's own format: side by side then reaches it as a plain copy.
        if ((*swapchain)->format() == VK_FORMAT_B8G8R8A8_UNORM || (*swapchain)->format() == VK_FORMAT_R8G8B8A8_UNORM) ro.colour_format = (*swapchain)->format();
        auto renderer = render::StereoRenderer::create(**ctx, ro);
        if (!renderer) {
            std::cerr << "ikebana: " << renderer.error().message << "\n";
            return 3;
        }
        // The session: the simulation on its own thread at 1 kHz (devices read and forces sent there,
        // with a watchdog), this thread drawing at the render rate from the snapshots it publishes.
        // The trainee_frame system below is this thread's whole job, run by the real-time clock.
        platform::GlfwPointerSource window_pointer((*window)->glfw());
        platform::PointerSource& pointer = o.pointer ? *o.pointer : static_cast<platform::PointerSource&>(window_pointer);
        platform::SharedPointerSource shared_pointer; // GLFW is read here, the hands read it there
        devices::MouseKeyboardHands mouse(shared_pointer);
        World* world_ptr = nullptr;
        render::DrawList sample_list;
        glm::dvec3 kenzan_at{0.0};
        render::StereoRig base_rig;
        base_rig.eye_separation_m = scene->display.eye_separation_m;
        base_rig.screen_distance_m = scene->display.screen_distance_m;
        base_rig.vertical_fov_rad = scene->display.vertical_fov_rad;
        double yaw = 0.0, pitch = 0.0;
        auto last = std::chrono::steady_clock::now();
        glm::dvec2 drag_from{0.0};
        bool dragging = false;
        std::uint32_t presented = 0;
        bool enter_was_down = false;
        std::vector<double> frame_ms, record_ms, shadow_ms, eyes_ms, composite_ms, present_ms;
        auto previous_frame = std::chrono::steady_clock::now();
        std::optional<render::RgbaImage> last_shot;
        std::atomic<bool> stop{false};

        auto frame_fn = [&](sched::SystemContext& main_lane) {
            if (stop.load()) return;
            World& w = *world_ptr;
            if (o.each_frame) o.each_frame(presented, (*window)->glfw());
            (*window)->poll_events();
            const platform::PointerState input = pointer.read();
            shared_pointer.store(input);
            if (input.quit_key) (*window)->request_close();
            if ((*window)->should_close()) {
                stop.store(true);
                return;
            }
            const auto now = std::chrono::steady_clock::now();
            const double dt = std::min(0.1, std::chrono::duration<double>(now - last).count());
            last = now;
            // Camera: during training, not only after it (the paper's future work).
            yaw += 1.2 * dt * input.arrows.x;
            pitch += 1.2 * dt * input.arrows.y;
            if (input.orbit_button) {
                if (dragging) {
                    yaw += 0.005 * (input.cursor_px.x - drag_from.x);
                    pitch += 0.005 * (input.cursor_px.y - drag_from.y);
                }
                dragging = true;
                drag_from = input.cursor_px;
            } else {
                dragging = false;
            }
            pitch = std::clamp(pitch, -0.5, 1.0);
            // "Forward" on the device stays "away from the viewer".
            w.view.yaw_rad.store(yaw, std::memory_order_relaxed);

            const VkExtent2D size = (*window)->framebuffer();
            if (size.width == 0 || size.height == 0) return; // minimised: nothing to draw, the simulation runs on
            if (size.width != (*swapchain)->extent().width || size.height != (*swapchain)->extent().height) {
                if (auto r = (*swapchain)->recreate(size); !r) {
                    std::cerr << "ikebana: " << r.error().message << "\n";
                    code = 3;
                    stop.store(true);
                    return;
                }
            }
            const auto* received = main_lane.registry.resource<systems::ReceivedFrames>();
            const components::FrameSnapshot& latest = received->latest;
            // Enter: the trainee is done; the result stays on screen and the session goes on.
            const bool enter = input.finish_key;
            if ((enter && !enter_was_down) || (o.finish_at_frame > 0 && presented + 1 == o.finish_at_frame)) {
                const auto result = score_arrangement(arranged_stems(latest), scene->sample, kenzan_at);
                hud.result = scene->sample.empty() ? std::vector<std::string>{"RESULT: free practice (this scene has no sample)"} : result.lines();
                for (const auto& line : hud.result) std::printf("%s\n", line.c_str());
            }
            enter_was_down = enter;
            render::DrawList drawn = latest.draw_list;
            drawn.append(sample_list);
            (*renderer)->set_overlay(hud_panels(latest, hud));
            const bool want_shot = !o.screenshot.empty() && o.frames > 0 && presented + 1 >= o.frames;
            auto frame = (*renderer)->present(**swapchain, drawn, render::orbited(base_rig, yaw, pitch), want_shot);
            if (!frame) {
                std::cerr << "ikebana: " << frame.error().message << "\n";
                code = 3;
                stop.store(true);
                return;
            }
            for (const auto& warning : (*renderer)->take_warnings()) std::cerr << "ikebana: warning: " << warning << "\n";
            if (frame->swapchain_stale) {
                if (auto r = (*swapchain)->recreate((*window)->framebuffer()); !r && (*window)->framebuffer().width > 0) {
                    std::cerr << "ikebana: " << r.error().message << "\n";
                    code = 3;
                    stop.store(true);
                    return;
                }
            }
            if (!frame->presented) return;
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
            if (presented % 15 == 0) glfwSetWindowTitle((*window)->glfw(), status_line(latest).c_str());
            if (o.frames > 0 && presented >= o.frames) stop.store(true);
        };
        sched::SystemDesc trainee_frame;
        trainee_frame.name = "trainee_frame";
        trainee_frame.lane = "main";
        trainee_frame.phase = "frame";
        trainee_frame.rate = "render"; // frames at the scheduler's render rate (30 Hz by default)
        trainee_frame.reads = sched::components<systems::ReceivedFrames>();
        trainee_frame.after = {std::string(systems::ReceiveFrameSystem::name)};
        trainee_frame.run = frame_fn;

        auto world = World::create(*scene, WorldOptions{.rate_overrides = o.rates, .force_scheme = {}, .main_lane_systems = {trainee_frame}});
        if (!world) {
            std::cerr << "ikebana: " << world.error().message << "\n";
            return 2;
        }
        World& w = **world;
        world_ptr = &w;
        for (std::uint8_t hand = 0; hand < 2; ++hand) w.attach_device(hand, picked[hand] ? std::move(picked[hand]) : mouse.hand(hand));
        add_sample_to_draw_list(sample_list, w, scene->sample);
        kenzan_at = kenzan_origin(w);
        std::printf("ikebana: %s on %s (%s); arrows or right-drag orbit the camera, Tab switches hands, Esc ends\n",
                    render::stereo_mode_name(*render_mode), (*ctx)->device_name().c_str(), (*renderer)->multiview() ? "multiview" : "one pass per eye");
        std::fflush(stdout);
        // The hands' first reading is the pointer as it is now, not an empty state (that would look like
        // a jump of the cursor from the corner).
        shared_pointer.store(pointer.read());
        std::vector<sched::LaneReport> lanes;
        {
            const HandForceWatchdogs watchdogs(w);
            sched::RealtimeClock clock(w.schedule, sched::RealtimeConfig{.max_catchup_us = 50'000, .own_thread_timer_slack_ns = 1'000, .own_thread_fifo_priority = 20});
            // Until the window closes or the frames asked for are presented.
            lanes = clock.run_for(1e9, &stop);
            std::printf("%s", format_realtime_report(w, lanes).c_str());
            for (std::size_t hand = 0; hand < 2; ++hand) {
                if (watchdogs.trips(hand) > 0)
                    std::printf("%s hand force watchdog: tripped %llu time(s)\n", hand ? "right" : "left",
                                static_cast<unsigned long long>(watchdogs.trips(hand)));
            }
        }
        for (std::size_t hand = 0; hand < 2; ++hand) {
            if (w.hand_devices[hand]) (void)w.hand_devices[hand]->send_force(glm::dvec3{0.0}); // nothing pushes after the session
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
        std::printf("ikebana: camera turned %.0f deg round, tilted %.0f deg\n", yaw * 180.0 / M_PI, pitch * 180.0 / M_PI);
        std::printf("ikebana: %u frames presented; %s\n", presented, status_line(w.main.resource<systems::ReceivedFrames>()->latest).c_str());
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
