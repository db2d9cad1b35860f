#include "game/app/trainee_app.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <atomic>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include <GLFW/glfw3.h>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "engine/devices/mouse_keyboard_device.hpp"
#include "engine/platform/pointer_input.hpp"
#include "game/app/pointer_aim.hpp"
#include "engine/platform/window.hpp"
#include "engine/render/stereo_renderer.hpp"
#include "engine/render/swapchain.hpp"
#include "engine/sched/clocks.hpp"
#include "engine/sched/rates.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/render_command.hpp"
#include "components/presentation.hpp"
#include "game/training/arrangement_score.hpp"
#include "game/training/sample_arrangement.hpp"
#include "game/devices/hand_device_selection.hpp"
#include "game/scene/scene.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"
#include "game/devices/force_watchdogs.hpp"
#include "game/lesson/form_score.hpp"
#include "game/lesson/lesson_controls.hpp"
#include "game/lesson/lesson.hpp"
#include "game/lesson/lesson_scene.hpp"
#include "game/lesson/window_state.hpp"
#include "systems/presentation/receive_frame_system.hpp"

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

// The main lane's two systems of the window: input (keys, pointer, camera, Enter) and draw (present
// what prepare_frame_system prepared). They call back into the session that owns the window.
struct WindowInputSystem {
    static constexpr std::string_view name = "window_input";
    static constexpr std::string_view lane = "main";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "render"; // frames at the scheduler's render rate (30 Hz by default)
    using reads = sched::Components<systems::ReceivedFrames>;
    using writes = sched::Components<components::HudInfo, components::Scenery>;
    std::function<void(sched::SystemContext&)> body;
    void operator()(sched::SystemContext& ctx) { body(ctx); }
};
struct WindowDrawSystem {
    static constexpr std::string_view name = "window_draw";
    static constexpr std::string_view lane = "main";
    static constexpr std::string_view phase = "draw";
    static constexpr std::string_view rate = "render";
    using reads = sched::Components<systems::ReceivedFrames, components::PreparedFrame>;
    using writes = sched::Components<>;
    std::function<void(sched::SystemContext&)> body;
    void operator()(sched::SystemContext& ctx) { body(ctx); }
};

// One training session in the window: open (scene, devices, window, Vulkan, world), a frame as two
// main-lane systems under the real-time clock (the simulation runs on its own 1 kHz thread), finish
// (forces to zero, screenshot, figures). Members are destroyed in reverse order: the world and the
// renderer before the surface, the surface before the Vulkan context.
class TraineeSession {
public:
    explicit TraineeSession(const TraineeAppOptions& options) : o_(options) {}
    // Opens the window and everything it needs. Without a display the session is rendered offscreen
    // instead and is over; so it is after an error (already said). Either way: the exit code.
    int open();
    [[nodiscard]] bool is_open() const noexcept { return world_ != nullptr; }
    int run_and_finish();
    int run_once();

private:
    struct SurfaceGuard {
        SurfaceGuard() = default;
        SurfaceGuard(const SurfaceGuard&) = delete;
        SurfaceGuard& operator=(const SurfaceGuard&) = delete;
        VkInstance instance = VK_NULL_HANDLE;
        VkSurfaceKHR surface = VK_NULL_HANDLE;
        ~SurfaceGuard() {
            if (surface) vkDestroySurfaceKHR(instance, surface, nullptr);
        }
    };
    void input(sched::SystemContext& main_lane);
    void lesson_keys(const platform::PointerState& in, sched::SystemContext& main_lane);
    void show_result(const std::vector<std::string>& lines, components::HudInfo& hud) const;
    int build_world();
    void draw(sched::SystemContext& main_lane);
    void fail(const std::string& message, int exit_code);
    void print_frame_times() const;

    const TraineeAppOptions& o_;
    std::optional<SceneDef> scene_;
    std::optional<LessonDef> lesson_;
    KenzanFootprint footprint_;
    std::optional<LessonControls> controls_; // a lesson's keys, rebuilt with the world
    WindowState state_;                      // --state-out's, kept from frame to frame (the last result)
    std::atomic<bool> restart_{false};
    render::DrawList sample_scenery_;
    std::array<std::unique_ptr<devices::HapticDevice>, 2> picked_;
    std::array<std::string, 2> device_names_;
    std::unique_ptr<platform::Window> window_;
    render::StereoMode mode_ = render::StereoMode::side_by_side;
    std::unique_ptr<render::VulkanContext> ctx_;
    SurfaceGuard surface_;
    std::unique_ptr<render::Swapchain> swapchain_;
    std::unique_ptr<render::StereoRenderer> renderer_;
    std::unique_ptr<platform::GlfwPointerSource> window_pointer_;
    platform::PointerSource* pointer_ = nullptr;
    platform::SharedPointerSource shared_pointer_; // GLFW is read here, the hands read it there
    std::unique_ptr<devices::MouseKeyboardHands> mouse_;
    std::unique_ptr<World> world_;

    glm::dvec3 kenzan_at_{0.0};
    render::StereoRig base_rig_;
    double yaw_ = 0.0, pitch_ = 0.0;
    PointerAim aim_;
    [[nodiscard]] PointerView pointer_view() const { return {render::orbited(base_rig_, yaw_, pitch_), mode_, yaw_}; }
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
    glm::dvec2 drag_from_{0.0};
    bool dragging_ = false;
    bool enter_was_down_ = false;
    std::uint32_t presented_ = 0;
    std::vector<double> frame_ms_, record_ms_, shadow_ms_, eyes_ms_, composite_ms_, present_ms_;
    std::chrono::steady_clock::time_point previous_frame_ = std::chrono::steady_clock::now();
    std::optional<render::RgbaImage> last_shot_;
    std::atomic<bool> stop_{false};
    int code_ = 0;
};

void TraineeSession::fail(const std::string& message, int exit_code) {
    std::cerr << "ikebana: " << message << "\n";
    code_ = exit_code;
    stop_.store(true);
}

int TraineeSession::open() {
    auto scene = load_scene(o_.scene);
    if (!o_.lesson.empty()) {
        auto lesson = load_lesson(o_.lesson);
        if (!lesson) {
            std::cerr << "ikebana: --lesson: " << lesson.error().message << "\n";
            return 2;
        }
        lesson_ = std::move(lesson).value();
        scene = scene_for_lesson(*lesson_);
        if (auto f = footprint_of(*lesson_); f) footprint_ = *f;
    }
    if (!scene) {
        std::cerr << "ikebana: " << scene.error().message << "\n";
        return 2;
    }
    if (auto env = apply_environment_overrides(scene->environment, o_.env); !env) {
        std::cerr << "ikebana: " << env.error().message << "\n";
        return 2;
    }
    scene_ = std::move(scene).value();
    // Rates are checked before anything opens, so that a bad one is an error with or without a display.
    for (const auto& assignment : o_.rates) {
        sched::RateTable rates = sched::RateTable::paper_defaults();
        if (auto r = rates.set_from_string(assignment); !r) {
            std::cerr << "ikebana: --rate: " << r.error().message << "\n";
            return 2;
        }
    }
    // Devices first: what the trainee holds decides how the hands move.
    const std::string* specs[2] = {&o_.left_device, &o_.right_device};
    for (std::uint8_t hand = 0; hand < 2; ++hand) {
        auto opened = open_hand_device(*specs[hand], hand);
        if (!opened) {
            std::cerr << "ikebana: " << (hand ? "--right: " : "--left: ") << opened.error().message << "\n";
            return 2;
        }
        std::printf("%s hand: %s%s\n", hand ? "right" : "left", opened->description.c_str(), opened->device ? "" : " (mouse and keyboard in the window)");
        picked_[hand] = std::move(opened->device);
        device_names_[hand] = picked_[hand] ? opened->description : "mouse and keyboard";
    }
    const std::string stereo = o_.stereo.empty() ? scene_->display.stereo : o_.stereo;
    auto window = platform::Window::create("Ikebana", o_.width, o_.height);
    if (!window) {
        TraineeAppOptions fallback = o_;
        fallback.stereo = stereo;
        return offscreen_instead(fallback, window.error().message);
    }
    window_ = std::move(window).value();
    auto render_mode = render::parse_stereo_mode(stereo);
    if (!render_mode) {
        std::cerr << "ikebana: " << render_mode.error().message << "\n";
        return 2;
    }
    mode_ = *render_mode;
    auto ctx = render::VulkanContext::create(
        {.validation = o_.validation, .require_validation = false, .instance_extensions = platform::Window::required_instance_extensions()});
    if (!ctx) {
        std::cerr << "ikebana: " << ctx.error().message << "\n";
        return 3;
    }
    ctx_ = std::move(ctx).value();
    auto surface = window_->create_surface(ctx_->instance());
    if (!surface) {
        std::cerr << "ikebana: " << surface.error().message << "\n";
        return 3;
    }
    surface_.instance = ctx_->instance(); // the guard is filled in place: a temporary would destroy the surface
    surface_.surface = *surface;
    auto swapchain = render::Swapchain::create(*ctx_, surface_.surface, window_->framebuffer());
    if (!swapchain) {
        std::cerr << "ikebana: " << swapchain.error().message << "\n";
        return 3;
    }
    swapchain_ = std::move(swapchain).value();
    render::RendererOptions ro;
    ro.mode = mode_;
    ro.asset_dir = asset_dir();
    ro.eye_width = std::max(1u, mode_ == render::StereoMode::side_by_side ? o_.width / 2 : o_.width);
    ro.eye_height = std::max(1u, o_.height);
    // The eyes in the window's own format: side by side then reaches it as a plain copy.
    if (swapchain_->format() == VK_FORMAT_B8G8R8A8_UNORM || swapchain_->format() == VK_FORMAT_R8G8B8A8_UNORM) ro.colour_format = swapchain_->format();
    auto renderer = render::StereoRenderer::create(*ctx_, ro);
    if (!renderer) {
        std::cerr << "ikebana: " << renderer.error().message << "\n";
        return 3;
    }
    renderer_ = std::move(renderer).value();
    window_pointer_ = std::make_unique<platform::GlfwPointerSource>(window_->glfw());
    // The window's own pointer is aimed through the camera (PointerAim), which keeps a Ctrl+drag off
    // the window's edge itself.
    pointer_ = o_.pointer ? o_.pointer : window_pointer_.get();
    mouse_ = std::make_unique<devices::MouseKeyboardHands>(shared_pointer_, lesson_ ? lesson_mouse_config() : devices::MouseKeyboardHands::Config{});
    // In a lesson the mouse's hands start where the lesson puts them, beside the materials. (Scenes
    // keep the mouse's own start, over the kenzan, which the window tests' gestures are measured from.)
    if (lesson_) {
        for (const auto& h : scene_->hands) mouse_->place(h.hand, h.position_m);
    }
    base_rig_ = rig_of(scene_->display);

    if (const int code = build_world(); code != 0) return code;
    std::printf("ikebana: %s on %s (%s); arrows or right-drag orbit the camera, Tab switches hands, Esc ends\n",
                render::stereo_mode_name(mode_), ctx_->device_name().c_str(), renderer_->multiview() ? "multiview" : "one pass per eye");
    std::fflush(stdout);
    return 0;
}


// The world of the session, built at the start and again when the trainee starts the lesson over
// (R): the same scene, the devices the hands had (their safety layer with them), the hands where the
// scene puts them.
int TraineeSession::build_world() {
    std::array<std::unique_ptr<devices::HapticDevice>, 2> kept;
    if (world_) {
        for (std::uint8_t hand = 0; hand < 2; ++hand) {
            if (device_names_[hand] != "mouse and keyboard") kept[hand] = std::move(world_->hand_devices[hand]);
        }
        world_.reset();
        if (lesson_) {
            for (const auto& h : scene_->hands) mouse_->place(h.hand, h.position_m);
        }
        aim_ = PointerAim{mouse_->active_hand()}; // the cursor goes onto the hand again where it starts
    } else {
        for (std::uint8_t hand = 0; hand < 2; ++hand) kept[hand] = std::move(picked_[hand]);
    }
    WindowInputSystem input_system;
    input_system.body = [this](sched::SystemContext& c) { input(c); };
    WindowDrawSystem draw_system;
    draw_system.body = [this](sched::SystemContext& c) { draw(c); };
    auto world = World::create(*scene_, WorldOptions{.rate_overrides = o_.rates,
                                                     .force_scheme = {},
                                                     .main_lane_systems = {sched::describe(input_system), sched::describe(draw_system)}});
    if (!world) {
        std::cerr << "ikebana: " << world.error().message << "\n";
        return 2;
    }
    world_ = std::move(world).value();
    for (const auto& warning : stability_warnings(*world_)) std::cerr << "ikebana: " << warning << "\n";
    for (std::uint8_t hand = 0; hand < 2; ++hand) world_->attach_device(hand, kept[hand] ? std::move(kept[hand]) : mouse_->hand(hand));
    world_->main.resource<components::HudInfo>()->device = device_names_;
    kenzan_at_ = kenzan_origin(*world_);
    sample_scenery_ = world_->main.resource<components::Scenery>()->list;
    if (lesson_) controls_.emplace(*lesson_, footprint_);
    return 0;
}

// Keys, pointer and camera; Enter scores the arrangement (the result stays on screen, the session goes on).
void TraineeSession::input(sched::SystemContext& main_lane) {
    if (stop_.load()) return;
    if (o_.each_frame) o_.each_frame(presented_, window_->glfw());
    window_->poll_events();
    platform::PointerState in = pointer_->read();
    const auto read_at = std::chrono::steady_clock::now();
    if (in.quit_key) window_->request_close();
    if (window_->should_close()) {
        stop_.store(true);
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    const double dt = std::min(0.1, std::chrono::duration<double>(now - last_).count());
    last_ = now;
    // Camera: during training, not only after it (the paper's future work).
    yaw_ += 1.2 * dt * in.arrows.x;
    pitch_ += 1.2 * dt * in.arrows.y;
    if (in.orbit_button) {
        if (dragging_) {
            yaw_ += 0.005 * (in.cursor_px.x - drag_from_.x);
            pitch_ += 0.005 * (in.cursor_px.y - drag_from_.y);
        }
        dragging_ = true;
        drag_from_ = in.cursor_px;
    } else {
        dragging_ = false;
    }
    pitch_ = std::clamp(pitch_, -0.5, 1.0);
    // "Forward" on the device stays "away from the viewer".
    world_->view.yaw_rad.store(yaw_, std::memory_order_relaxed);
    // The cursor aimed through the camera as drawn this frame, and kept on the hand it drives (a
    // test's scripted pointer moves the hands by the window's size instead).
    const PointerView view = pointer_view();
    if (pointer_ == window_pointer_.get()) {
        const auto& latest = main_lane.registry.resource<const systems::ReceivedFrames>()->latest();
        std::array<std::optional<glm::dvec3>, 2> hands;
        for (std::size_t h = 0; h < 2; ++h) {
            if (latest.hands[h].present) hands[h] = latest.hands[h].device_m;
        }
        aim_.aim(in, view, hands, [&](glm::dvec2 px) { window_pointer_->put_cursor(px); });
    }
    shared_pointer_.store(in);
    platform::PointerState keys = in;
    if (o_.finish_at_frame > 0 && presented_ + 1 == o_.finish_at_frame) keys.finish_key = true; // a test's Enter
    if (lesson_) lesson_keys(keys, main_lane); // a form lesson's Enter is scored there
    const bool form = lesson_ && lesson_->scoring == "form";
    if (!form && keys.finish_key && !enter_was_down_) {
        const auto& latest = main_lane.registry.resource<const systems::ReceivedFrames>()->latest();
        const auto result = score_arrangement(arranged_stems(latest), scene_->sample, kenzan_at_);
        show_result(scene_->sample.empty() ? std::vector<std::string>{"RESULT: free practice (this scene has no sample)"} : result.lines(),
                    *main_lane.registry.resource<components::HudInfo>());
    }
    enter_was_down_ = keys.finish_key;
    if (!o_.state_out.empty()) {
        state_.frame += 1;
        state_.input_read_at_us = std::chrono::duration_cast<std::chrono::microseconds>(read_at.time_since_epoch()).count();
        state_.window_px = in.window_px;
        state_.cursor_px = in.cursor_px;
        take_snapshot(state_, main_lane.registry.resource<const systems::ReceivedFrames>()->latest());
        state_.active_hand = aim_.active_hand();
        state_.px_per_m = glm::dvec2{0.0};
        if (in.ray.valid) {
            const auto gain = px_per_m_at(view, in.window_px, in.ray.eye, state_.hands[state_.active_hand].device_m);
            if (gain) state_.px_per_m = *gain;
        }
        if (auto written = write_window_state(o_.state_out, state_); !written) fail("--state-out: " + written.error().message, 2);
    }
}

// A result on the terminal and on screen (where a lesson's long tips are wrapped to an eye's half).
void TraineeSession::show_result(const std::vector<std::string>& lines, components::HudInfo& hud) const {
    for (const auto& line : lines) std::printf("%s\n", line.c_str());
    std::fflush(stdout);
    hud.result.clear();
    for (const auto& line : lines) {
        if (!lesson_) {
            hud.result.push_back(line);
            continue;
        }
        for (auto& part : hud_lines_of(line)) hud.result.push_back(std::move(part));
    }
}

// A lesson's keys (LessonControls: the same object a scripted mouse drives) and what the HUD says
// about the lesson and the stem in the hand.
void TraineeSession::lesson_keys(const platform::PointerState& in, sched::SystemContext& main_lane) {
    const auto& latest = main_lane.registry.resource<const systems::ReceivedFrames>()->latest();
    auto& hud = *main_lane.registry.resource<components::HudInfo>();
    const auto effects = controls_->update(in, mouse_->active_hand(), latest, world_->trainee);
    hud.lesson = controls_->hud_lines();
    if (!effects.cut_for.empty()) std::printf("ikebana: cut for %s to %.0f mm\n", effects.cut_for.c_str(), effects.cut_to_m * 1e3);
    if (effects.ghosts_toggled) {
        auto& scenery = *main_lane.registry.resource<components::Scenery>();
        scenery.list = sample_scenery_;
        scenery.labels.clear();
        if (controls_->ghosts()) {
            add_form_ghosts(scenery.list, *lesson_, footprint_, kenzan_at_);
            add_model_flowers(scenery.list, *lesson_, footprint_, model_plate_origin(*lesson_, kenzan_at_), world_->species);
            scenery.labels = form_labels(*lesson_, footprint_, kenzan_at_, model_plate_origin(*lesson_, kenzan_at_));
        }
    }
    if (effects.score && effects.score->ok()) {
        state_.results += 1;
        state_.result_json = (*effects.score)->json(-1);
    }
    if (effects.score) show_result(effects.score->ok() ? (*effects.score)->lines() : std::vector<std::string>{"RESULT: " + effects.score->error().message}, hud);
    if (effects.restart) {
        restart_.store(true);
        stop_.store(true);
    }
}

// Presents what the prepare phase made of this frame.
void TraineeSession::draw(sched::SystemContext& main_lane) {
    if (stop_.load()) return;
    const VkExtent2D size = window_->framebuffer();
    if (size.width == 0 || size.height == 0) return; // minimised: nothing to draw, the simulation runs on
    if (size.width != swapchain_->extent().width || size.height != swapchain_->extent().height) {
        if (auto r = swapchain_->recreate(size); !r) return fail(r.error().message, 3);
    }
    const auto& prepared = *main_lane.registry.resource<const components::PreparedFrame>();
    renderer_->set_overlay(prepared.overlay);
    const bool want_shot = !o_.screenshot.empty() && o_.frames > 0 && presented_ + 1 >= o_.frames;
    auto frame = renderer_->present(*swapchain_, prepared.list, render::orbited(base_rig_, yaw_, pitch_), want_shot);
    if (!frame) return fail(frame.error().message, 3);
    for (const auto& warning : renderer_->take_warnings()) std::cerr << "ikebana: warning: " << warning << "\n";
    if (frame->swapchain_stale) {
        if (auto r = swapchain_->recreate(window_->framebuffer()); !r && window_->framebuffer().width > 0) return fail(r.error().message, 3);
    }
    if (!frame->presented) return;
    ++presented_;
    const auto frame_end = std::chrono::steady_clock::now();
    frame_ms_.push_back(std::chrono::duration<double, std::milli>(frame_end - previous_frame_).count());
    previous_frame_ = frame_end;
    record_ms_.push_back(frame->timing.record_ms);
    shadow_ms_.push_back(frame->timing.shadow_ms);
    eyes_ms_.push_back(frame->timing.scene_ms);
    composite_ms_.push_back(frame->timing.composite_ms);
    present_ms_.push_back(frame->timing.present_ms);
    if (frame->screenshot) last_shot_ = std::move(frame->screenshot);
    if (presented_ % 15 == 0) glfwSetWindowTitle(window_->glfw(), status_line(main_lane.registry.resource<const systems::ReceivedFrames>()->latest()).c_str());
    if (o_.frames > 0 && presented_ >= o_.frames) stop_.store(true);
}

void TraineeSession::print_frame_times() const {
    if (frame_ms_.size() <= 2) return;
    auto whole = frame_ms_;
    whole.erase(whole.begin()); // the first frame includes start-up
    std::printf("frame time, ms (p50 / p95): whole frame %.1f / %.1f; record %.2f / %.2f; device: shadow %.1f / %.1f, both eyes %.1f / %.1f, "
                "composite and HUD %.1f / %.1f; present %.2f / %.2f\n",
                percentile(whole, 0.5), percentile(whole, 0.95), percentile(record_ms_, 0.5), percentile(record_ms_, 0.95),
                percentile(shadow_ms_, 0.5), percentile(shadow_ms_, 0.95), percentile(eyes_ms_, 0.5), percentile(eyes_ms_, 0.95),
                percentile(composite_ms_, 0.5), percentile(composite_ms_, 0.95), percentile(present_ms_, 0.5), percentile(present_ms_, 0.95));
}

int TraineeSession::run_and_finish() {
    for (;;) {
        const int code = run_once();
        if (!restart_.exchange(false) || code_ != 0) return code;
        // R: the lesson again from the start, in the same window.
        stop_.store(false);
        if (const int built = build_world(); built != 0) return built;
        std::printf("ikebana: started over\n");
    }
}

int TraineeSession::run_once() {
    World& w = *world_;
    // The hands' first reading is the pointer as it is now, not an empty state (that would look like
    // a jump of the cursor from the corner).
    shared_pointer_.store(pointer_->read());
    {
        const HandForceWatchdogs watchdogs(w);
        sched::RealtimeClock clock(w.schedule, sched::RealtimeConfig{.max_catchup_us = 50'000, .own_thread_timer_slack_ns = 1'000, .own_thread_fifo_priority = 20});
        // Until the window closes or the frames asked for are presented.
        const auto lanes = clock.run_for(1e9, &stop_);
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
    if (!o_.screenshot.empty()) {
        if (!last_shot_) {
            std::cerr << "ikebana: no screenshot: the window's images cannot be copied from on this device\n";
            code_ = code_ ? code_ : 1;
        } else if (auto wr = render::write_png(o_.screenshot, *last_shot_); !wr) {
            std::cerr << "ikebana: " << wr.error().message << "\n";
            code_ = code_ ? code_ : 1;
        } else {
            std::printf("ikebana: screenshot in %s\n", o_.screenshot.c_str());
        }
    }
    std::printf("ikebana: camera turned %.0f deg round, tilted %.0f deg\n", yaw_ * 180.0 / M_PI, pitch_ * 180.0 / M_PI);
    std::printf("ikebana: %u frames presented; %s\n", presented_, status_line(w.main.resource<const systems::ReceivedFrames>()->latest()).c_str());
    print_frame_times();
    if (ctx_->validation_enabled()) {
        std::printf("validation: %u errors, %u warnings\n", ctx_->validation_errors(), ctx_->validation_warnings());
        if (ctx_->validation_errors() > 0 && code_ == 0) code_ = 4;
    }
    vkDeviceWaitIdle(ctx_->device());
    return code_;
}

} // namespace

int run_trainee_app(const TraineeAppOptions& o) {
    TraineeSession session(o);
    const int code = session.open();
    return session.is_open() ? session.run_and_finish() : code;
}

} // namespace ikebana::game
