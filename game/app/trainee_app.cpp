#include "game/app/trainee_app.hpp"

#include "engine/core/emergency_stop.hpp"
#include "engine/devices/hid_transport.hpp"
#include "game/session/session_report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <atomic>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <thread>

#include <GLFW/glfw3.h>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "engine/devices/mouse_keyboard_device.hpp"
#include "engine/platform/pointer_input.hpp"
#include "game/render/pointer_aim.hpp"
#include "game/app/replay_window.hpp"
#include "game/app/panel_pointer.hpp"
#include "game/app/session_panel.hpp"
#include "game/lesson/role_colours.hpp"
#include "engine/render/screen_layout.hpp"
#include "systems/presentation/hud.hpp"
#include "game/app/lesson_flow.hpp"
#include "game/app/start_screen.hpp"
#include "game/app/stored_sessions.hpp"
#include "game/app/window_camera.hpp"
#include "game/render/frame_timings.hpp"
#include "game/app/window_stack.hpp"
#include "engine/render/ui_layer.hpp"
#include "engine/platform/window.hpp"
#include "engine/render/stereo_renderer.hpp"
#include "engine/render/swapchain.hpp"
#include "engine/sched/clocks.hpp"
#include "engine/sched/rates.hpp"
#include "engine/assets/files.hpp"
#include "game/asset_paths.hpp"
#include "game/render/offscreen_render.hpp"
#include "components/presentation.hpp"
#include "game/training/arrangement_score.hpp"
#include "game/world/sample_arrangement.hpp"
#include "game/devices/hand_device_selection.hpp"
#include "game/scene/scene.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"
#include "game/devices/force_watchdogs.hpp"
#include "game/training/form_score.hpp"
#include "game/session/lesson_controls.hpp"
#include "game/lesson/lesson.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/session/lesson_session.hpp"
#include "game/session/window_state.hpp"
#include "game/progress/progress_db.hpp"
#include "systems/haptics/trainee_command_system.hpp"
#include "systems/haptics/workspace_view_system.hpp"
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

int offscreen_instead(const TraineeAppOptions& o, const std::string& why) {
    const auto out = (std::filesystem::temp_directory_path() / "ikebana-frames").string();
    std::printf("ikebana: %s; rendering the scene offscreen instead\n", why.c_str());
    std::fflush(stdout);
    RenderOptions r;
    r.scene = o.scene;
    // A picture of the scene, not a session: `--frames` counts a window's frames (a script asks for
    // 100,000 and ends its session otherwise), and as many offscreen PNGs would take hours.
    r.frames = std::min<std::uint32_t>(o.frames > 0 ? o.frames : 30, 120);
    r.stereo = o.stereo;
    r.out = out;
    r.width = o.stereo == "sbs" ? std::max(16u, o.width / 2) : o.width;
    r.height = o.height;
    r.validation = o.validation;
    const int code = run_render(r);
    if (code == 0) std::printf("ikebana: the images are in %s\n", out.c_str());
    return code;
}

class TraineeSession;

// The main lane's four systems of the window, at the scheduler's render rate (30 Hz by default):
// input (the window's events, the lesson's panel, the camera, the cursor's aim), the lesson's flow
// (what the keys do: LessonFlow), the frame's state for --state-out (before drawing: a driver waiting
// on it is not kept waiting for the frame's drawing too), and draw (present what prepare_frame_system prepared). What they touch of the world is declared and checked
// like any system's; the window, Dear ImGui, the progress database and the state file are the
// session's own, and no other system touches them.
// What the four share: the main lane, a frame at the render rate, the session they work for.
struct OnTheWindowFrame {
    static constexpr std::string_view lane = "main";
    static constexpr std::string_view rate = "render";
    TraineeSession* session = nullptr;
};
struct WindowInputSystem : OnTheWindowFrame {
    static constexpr std::string_view name = "window_input";
    static constexpr std::string_view phase = "input";
    using reads = sched::Components<systems::ReceivedFrames, components::HudInfo>; // the panel shows the HUD's text
    using writes = sched::Components<ecs::Port<systems::ViewChannel>>; // the camera's turn goes to the hands' workspace
    void operator()(sched::SystemContext& ctx);
};
struct LessonFlowSystem : OnTheWindowFrame {
    static constexpr std::string_view name = "lesson_flow";
    static constexpr std::string_view phase = "input"; // after window_input
    using reads = sched::Components<systems::ReceivedFrames>;
    // The HUD's lines and the ghosts; a cut goes to the simulation.
    using writes = sched::Components<components::HudInfo, components::Scenery, ecs::Port<systems::TraineeChannel>>;
    void operator()(sched::SystemContext& ctx);
};
struct WindowDrawSystem : OnTheWindowFrame {
    static constexpr std::string_view name = "window_draw";
    static constexpr std::string_view phase = "draw";
    using reads = sched::Components<systems::ReceivedFrames, components::PreparedFrame>;
    using writes = sched::Components<>;
    void operator()(sched::SystemContext& ctx);
};
struct WindowStateSystem : OnTheWindowFrame {
    static constexpr std::string_view name = "window_state";
    static constexpr std::string_view phase = "input"; // after lesson_flow (its result is in the state)
    using reads = sched::Components<systems::ReceivedFrames>;
    using writes = sched::Components<>;
    void operator()(sched::SystemContext& ctx);
};

// One training session in the window: open (scene, devices, window, Vulkan, world), a frame as four
// main-lane systems under the real-time clock (the simulation runs on its own 1 kHz thread), finish
// (forces to zero, screenshot, figures). Members are destroyed in reverse order: the world and the
// renderer before the surface, the surface before the Vulkan context.
class TraineeSession {
public:
    explicit TraineeSession(const TraineeAppOptions& options) : o_(options), stored_(options) {}
    // Opens the window and everything it needs. Without a display the session is rendered offscreen
    // instead and is over; so it is after an error (already said). Either way: the exit code.
    int open();
    [[nodiscard]] bool is_open() const noexcept { return opened_; }
    int run_and_finish();
    int run_once();

    // The window systems' bodies (main lane, each frame).
    void input(sched::SystemContext& main_lane);
    void lesson_flow(sched::SystemContext& main_lane);
    void draw(sched::SystemContext& main_lane);
    void write_state(sched::SystemContext& main_lane);

private:
    int build_world();
    // The lesson (or the scene) the window shows: loaded, then its hands and world.
    int load_content(const std::string& lesson);
    int enter_content();
    // The start screen until a lesson is chosen (its id) or the trainee leaves (nullopt).
    std::optional<std::string> run_start_screen();
    void write_screenshot();
    void fail(const std::string& message, int exit_code);
    void report_figures(const std::string& figures) const;

    const TraineeAppOptions& o_;
    std::optional<SceneDef> scene_;
    std::optional<LessonDef> lesson_;
    KenzanFootprint footprint_;
    std::optional<LessonFlow> flow_; // what the keys do, rebuilt with the world
    WindowState state_;                      // --state-out's, kept from frame to frame (the last result)
    std::atomic<bool> restart_{false};
    std::array<std::unique_ptr<devices::HapticDevice>, 2> picked_;
    std::array<std::string, 2> device_names_;
    // The window and what draws into it; the pointers below are its parts (null until it opens).
    std::unique_ptr<WindowStack> stack_;
    platform::Window* window_ = nullptr;
    render::StereoMode mode_ = render::StereoMode::side_by_side;
    render::VulkanContext* ctx_ = nullptr;
    render::StereoRenderer* renderer_ = nullptr;
    platform::GlfwPointerSource* window_pointer_ = nullptr;
    render::UiLayer* ui_ = nullptr; // Dear ImGui: the start screen and the lesson's panel (null without it)
    StartScreen start_screen_;
    StartScreenModel start_model_;
    SessionPanel panel_;
    double column_px_ = 0.0;     // kept right of each eye's scene for the panel (render::ScreenLayout)
    glm::dvec2 window_size_px_{1.0}; // the window's, as laid out this frame
    glm::dvec2 panel_tilt_{0.0}; // the panel's tilt buttons, counted as Ctrl+arrow presses
    [[nodiscard]] SessionPanelModel panel_model(sched::SystemContext& main_lane) const;
    bool showing_start_ = false;
    bool opened_ = false;
    std::atomic<bool> back_{false}; // Esc or the panel's button in a lesson: back to the start screen
    platform::PointerSource* pointer_ = nullptr;
    platform::SharedPointerSource shared_pointer_; // GLFW is read here, the hands read it there
    PanelPointer hands_; // what the hands were last given, the cursor over the panel or in the scene
    std::unique_ptr<devices::MouseKeyboardHands> mouse_;
    std::unique_ptr<World> world_;

    glm::dvec3 kenzan_at_{0.0};
    WindowCamera camera_;
    PointerAim aim_;
    [[nodiscard]] PointerView pointer_view() const { return {camera_.rig(), mode_, camera_.yaw_rad(), column_px_}; }
    // This frame's reading as aimed, kept from input for the state written after it.
    platform::PointerState read_;
    std::chrono::steady_clock::time_point read_at_ = std::chrono::steady_clock::now();
    bool frame_read_ = false; // this frame's input was read in full (the lesson and the state take it)
    platform::PointerState keys_; // this frame's keys for the lesson (the panel's buttons pressed too)
    std::uint32_t presented_ = 0;
    FrameTimings timings_;
    std::optional<render::RgbaImage> last_shot_;
    std::atomic<bool> stop_{false};
    int code_ = 0;
    // The trainee's progress: each scored session of a lesson stored, and recorded for replay.
    StoredSessions stored_;
    std::string report_note_; // where the Report button's last report went, or why it did not
    void write_report();
};

void WindowInputSystem::operator()(sched::SystemContext& ctx) { session->input(ctx); }
void LessonFlowSystem::operator()(sched::SystemContext& ctx) { session->lesson_flow(ctx); }
void WindowDrawSystem::operator()(sched::SystemContext& ctx) { session->draw(ctx); }
void WindowStateSystem::operator()(sched::SystemContext& ctx) { session->write_state(ctx); }

void TraineeSession::fail(const std::string& message, int exit_code) {
    std::cerr << "ikebana: " << message << "\n";
    code_ = exit_code;
    stop_.store(true);
}

// A lesson by its id (or the scene of --scene when empty): its scene, kenzan and environment.
int TraineeSession::load_content(const std::string& lesson_id) {
    auto scene = load_scene(o_.scene);
    lesson_.reset();
    if (!lesson_id.empty()) {
        auto lesson = load_lesson(lesson_id);
        if (!lesson) {
            std::cerr << "ikebana: --lesson: " << lesson.error().message << "\n";
            return 2;
        }
        lesson_ = std::move(lesson).value();
        scene = scene_for_lesson(*lesson_);
        if (auto f = footprint_of(*lesson_); f) footprint_ = *f;
    }
    scene = with_environment(std::move(scene), o_.env);
    if (!scene) {
        std::cerr << "ikebana: " << scene.error().message << "\n";
        return 2;
    }
    scene_ = std::move(scene).value();
    return 0;
}

int TraineeSession::open() {
    showing_start_ = o_.start_screen && o_.lesson.empty();
    if (const int code = load_content(o_.lesson); code != 0) return code;
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
    auto window = platform::Window::create("Ikebana", o_.width, o_.height);
    if (!window) {
        TraineeAppOptions fallback = o_;
        fallback.stereo = o_.stereo.empty() ? scene_->display.stereo : o_.stereo;
        return offscreen_instead(fallback, window.error().message);
    }
    const auto kept = stored_.open(showing_start_, lesson_ ? &*lesson_ : nullptr);
    start_model_.progress_note = kept.note;
    if (!kept.trainee.empty()) start_model_.trainee = kept.trainee;
    // How the scene is shown: --stereo; else as this trainee chose on the start screen last time; else a
    // flat screen (one view, the whole width: a first-time trainee's screen), from the start screen or
    // straight into a lesson alike. The scene's own display (its eyes' separation, its distance) is
    // what the stereo modes use once chosen; `ikebana --lesson ...` as the README has a newcomer type
    // it once opened side by side on a flat screen.
    std::string stereo = o_.stereo;
    if (stereo.empty()) {
        if (auto remembered = stored_.remembered("display"); remembered && render::parse_stereo_mode(*remembered)) stereo = *remembered;
    }
    if (stereo.empty()) stereo = "mono";
    auto render_mode = render::parse_stereo_mode(stereo);
    if (!render_mode) {
        std::cerr << "ikebana: " << render_mode.error().message << "\n";
        return 2;
    }
    mode_ = *render_mode;
    auto stack = WindowStack::open(std::move(window).value(), {.width = o_.width, .height = o_.height, .mode = mode_, .validation = o_.validation, .need_ui = showing_start_, .msaa = o_.msaa, .full_detail = o_.full_detail});
    if (!stack) {
        std::cerr << "ikebana: " << stack.error().message << "\n";
        return 3;
    }
    stack_ = std::move(stack).value();
    window_ = &stack_->window();
    ctx_ = &stack_->vulkan();
    renderer_ = &stack_->renderer();
    window_pointer_ = &stack_->pointer();
    ui_ = stack_->ui();
    if (!ui_) std::cerr << "ikebana: warning: no panels: " << stack_->ui_problem() << "\n";
    // The window's own pointer is aimed through the camera (PointerAim), which keeps a Ctrl+drag off
    // the window's edge itself.
    pointer_ = o_.pointer ? o_.pointer : window_pointer_;
    camera_.reset(rig_of(scene_->display));
    start_model_.display = render::stereo_mode_name(mode_);
    start_model_.display_fixed = !o_.stereo.empty();
    state_.display = start_model_.display;
    if (showing_start_) {
        auto lessons = load_shipped_lessons();
        if (lessons) start_model_.lessons = std::move(lessons).value();
        order_for_newcomers(start_model_.lessons);
        start_model_.hands = device_names_;
    } else if (const int code = enter_content(); code != 0) {
        return code;
    }
    opened_ = true;
    std::printf("ikebana: %s on %s (%s, %ux anti-aliasing); arrows or right-drag orbit the camera, Tab switches hands, Esc ends\n",
                render::stereo_mode_name(mode_), ctx_->device_name().c_str(), renderer_->multiview() ? "multiview" : "one pass per eye", renderer_->samples());
    std::fflush(stdout);
    return 0;
}


// Into the lesson (or scene) loaded: the mouse's hands where it puts them, the camera back, its world.
int TraineeSession::enter_content() {
    // The old hands stay until the old world, which holds them, is gone (build_world).
    auto old_mouse = std::move(mouse_);
    mouse_ = std::make_unique<devices::MouseKeyboardHands>(shared_pointer_, lesson_ ? lesson_mouse_config() : devices::MouseKeyboardHands::Config{});
    // In a lesson the mouse's hands start where the lesson puts them, beside the materials. (Scenes
    // keep the mouse's own start, over the kenzan, which the window tests' gestures are measured from.)
    if (lesson_) {
        for (const auto& h : scene_->hands) mouse_->place(h.hand, h.position_m);
    }
    camera_.reset(rig_of(scene_->display));
    aim_ = PointerAim{};
    const int code = build_world();
    if (world_ && showing_start_ == false && ui_ && window_pointer_) window_pointer_->forget_taps(); // letters typed into the name are no cuts
    return code;
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
        mouse_->restart();
        if (lesson_) {
            for (const auto& h : scene_->hands) mouse_->place(h.hand, h.position_m);
        }
        aim_ = PointerAim{mouse_->active_hand()}; // the cursor goes onto the hand again where it starts
    } else {
        for (std::uint8_t hand = 0; hand < 2; ++hand) kept[hand] = std::move(picked_[hand]);
    }
    auto world = World::create(*scene_, WorldOptions{.rate_overrides = o_.rates,
                                                     .force_scheme = {},
                                                     .main_lane_systems = {sched::describe(WindowInputSystem{{this}}), sched::describe(WindowDrawSystem{{this}}),
                                                                           sched::describe(LessonFlowSystem{{this}}, {std::string(WindowInputSystem::name)}),
                                                                           sched::describe(WindowStateSystem{{this}}, {std::string(LessonFlowSystem::name)})}});
    if (!world) {
        std::cerr << "ikebana: " << world.error().message << "\n";
        return 2;
    }
    world_ = std::move(world).value();
    for (const auto& warning : startup_warnings(*world_)) std::cerr << "ikebana: " << warning << "\n";
    for (std::uint8_t hand = 0; hand < 2; ++hand) world_->attach_device(hand, kept[hand] ? std::move(kept[hand]) : mouse_->hand(hand));
    world_->main.resource<components::HudInfo>()->device = device_names_;
    kenzan_at_ = kenzan_origin(*world_);
    flow_.emplace(lesson_ ? &*lesson_ : nullptr, footprint_, scene_->sample, kenzan_at_, world_->main.resource<components::Scenery>()->list, world_->species);
    stored_.begin(*world_, lesson_ ? &*lesson_ : nullptr);
    report_note_.clear(); // a new session: the last one's report is not this one's
    return 0;
}

// The Report button: the session as its last Enter scored it, with this trainee's trend, as PNG and
// PDF beside its recording (or under the progress database's folder when it has none). About 50 ms of
// the frame's lane, once per press.
void TraineeSession::write_report() {
    SessionRecord session = stored_.session();
    // The last Enter's result, kept by the lesson's flow whether or not a database took it.
    if (flow_ && flow_->last_score()) session.result = *flow_->last_score();
    if (session.result.lesson.empty()) {
        report_note_ = "score it first (Enter)";
        return;
    }
    if (session.lesson.empty()) session.lesson = session.result.lesson;
    auto report = session_report_for(session, stored_.db());
    if (!report) {
        report_note_ = "no report: " + report.error().message;
        return;
    }
    const std::filesystem::path dir = !session.recording.empty() ? std::filesystem::path(session.recording) / "report"
                                      : (o_.progress_db.empty() ? default_progress_path() : std::filesystem::path(o_.progress_db)).parent_path() / "reports" /
                                            ("session-" + std::to_string(session.id > 0 ? session.id : session.started_unix_s));
    if (auto written = write_session_report(*report, dir); !written) {
        report_note_ = "no report: " + written.error().message;
        return;
    }
    report_note_ = "report (PNG and PDF) in " + dir.string();
    std::printf("ikebana: the session's report is in %s (report.png, report.pdf)\n", dir.c_str());
}

// What the panel shows this frame: the lesson's next step and advice, the form's legend with G, the
// last result, the heads-up text and the controls.
SessionPanelModel TraineeSession::panel_model(sched::SystemContext& main_lane) const {
    SessionPanelModel m;
    m.title = lesson_ ? lesson_->school + ": " + lesson_->title : "Free practice";
    m.trainee = stored_.trainee();
    const auto& latest = main_lane.registry.resource<const systems::ReceivedFrames>()->latest();
    const LessonControls* controls = flow_ ? flow_->controls() : nullptr;
    m.next_step = controls ? controls->next_step() : "arrange the flowers like the sample beside the container, then Score (Enter)";
    if (controls) {
        m.held = controls->advice();
        m.gauge = controls->gauge();
        if (m.gauge) m.role_colour = role_colour(m.gauge->role).rgb;
    }
    m.holding = latest.hands[aim_.active_hand() & 1u].holding;
    m.ghosts_on = flow_ && flow_->ghosts();
    if (m.ghosts_on && lesson_) {
        for (std::size_t i = 0; i < lesson_->stems.size(); ++i) m.legend.push_back({lesson_->stems[i].role, role_colour(i).rgb, role_target_words(*lesson_, i)});
    }
    if (flow_) m.result = flow_->result();
    if (flow_ && flow_->last_score()) show_score(m, *flow_->last_score(), lesson_ ? &*lesson_ : nullptr);
    m.report_note = report_note_;
    components::HudInfo plain = *main_lane.registry.resource<const components::HudInfo>();
    plain.keys.clear();
    plain.lesson.clear();
    plain.result.clear();
    m.details = systems::hud_lines(latest, plain);
    m.controls = {"Move the mouse: the hand (the cube) goes where the cursor points; pointing at a stem, it goes onto that stem",
                  "Hold the left button: take the stem under the cube (it shows yellow); release: let go",
                  "Wheel: the hand further away or nearer along your line of sight (away also takes it lower)",
                  "Shift+move up and down: the hand further away or nearer at the same height",
                  "Ctrl+drag: lean the held stem as you see it: right leans it right, up leans it away from you, a degree for 4 pixels on its gauge",
                  "Ctrl+arrow keys, or the Tilt buttons: lean it 5° that way",
                  "Ctrl+Shift+drag sideways: twist the held stem about itself (where a bend or a branch faces)",
                  "Ctrl+wheel: swing its lean round the vertical, 5° a notch (wheel up: counterclockwise seen from above)",
                  "C: cut the held stem to its role's length",
                  "P: prune at the cube: the twig it touches off at its fork, or the leaf or blossom it touches stripped",
                  "Tab: the other hand",
                  "Arrow keys (15° a press) or right-drag: look round the table",
                  "G: the form's targets and model; Enter: score; R: start over; Esc: the lessons"};
    return m;
}

// Keys, pointer and camera; Enter scores the arrangement (the result stays on screen, the session goes on).
void TraineeSession::input(sched::SystemContext& main_lane) {
    frame_read_ = false;
    if (stop_.load()) return;
    if (o_.each_frame) o_.each_frame(presented_, window_->glfw());
    window_->poll_events();
    platform::PointerState in = pointer_->read();
    read_at_ = std::chrono::steady_clock::now();
    // The panel's column beside the scene (without Dear ImGui there is none, and the HUD is drawn over
    // the scene instead). Its buttons do what the keys do.
    int width = 1, height = 1;
    glfwGetWindowSize(window_->glfw(), &width, &height);
    window_size_px_ = glm::dvec2{std::max(width, 1), std::max(height, 1)};
    const render::ScreenLayout whole{mode_, window_size_px_, 0.0};
    column_px_ = ui_ ? std::floor(session_column_px(whole.area_width_px())) : 0.0;
    renderer_->set_column(static_cast<std::uint32_t>(column_px_));
    SessionPanelActions act;
    if (ui_) {
        ui_->begin_frame(mode_);
        act = panel_.draw(panel_model(main_lane), static_cast<float>(whole.area_width_px() - column_px_), static_cast<float>(column_px_));
        ui_->end_frame();
    }
    panel_tilt_ += act.tilt_steps;
    // Over the panel (or off the scene) the cursor is the trainee's to click with, not the hand's; a
    // Ctrl+drag goes on (the aim puts the cursor back in the scene's middle at its edge).
    const bool over_panel = ui_ && !in.tilt_modifier && (ui_->wants_pointer() || !pointer_view().layout(window_size_px_).in_scene(in.cursor_px));
    if (in.quit_key || act.back) {
        // From a lesson opened on the start screen, Esc goes back there; otherwise it ends.
        if (o_.start_screen) {
            back_.store(true);
            stop_.store(true);
            return;
        }
        window_->request_close();
    }
    if (window_->should_close()) {
        stop_.store(true);
        return;
    }
    camera_.turn(in);
    in.view_yaw_rad = camera_.yaw_rad();
    in.tilt_presses += panel_tilt_;
    // "Forward" on the device stays "away from the viewer".
    main_lane.registry.resource<ecs::Port<systems::ViewChannel>>()->use().yaw_rad.store(camera_.yaw_rad(), std::memory_order_relaxed);
    // The cursor aimed through the camera as drawn this frame, and kept on the hand it drives (a
    // test's scripted pointer moves the hands by the window's size instead).
    const PointerView view = pointer_view();
    if (pointer_ == window_pointer_) {
        const auto& latest = main_lane.registry.resource<const systems::ReceivedFrames>()->latest();
        std::array<std::optional<glm::dvec3>, 2> hands;
        for (std::size_t h = 0; h < 2; ++h) {
            if (latest.hands[h].present) hands[h] = latest.hands[h].device_m;
        }
        // Over the panel the cursor is the trainee's to click with, not the hand's.
        if (!over_panel) aim_.aim(in, view, hands, [&](glm::dvec2 px) { window_pointer_->put_cursor(px); });
    }
    // A held stem in the pins turns about its bottom, where the pins hold it, not about the hand's
    // grip; and a lean moves its tip the way asked, knowing which way it points.
    // (The hands' own idea of which is active: a Tab pressed over the panel reaches them, not the aim.)
    tell_held_stem(in, main_lane.registry.resource<const systems::ReceivedFrames>()->latest(), mouse_ ? mouse_->active_hand() : aim_.active_hand(),
                   camera_.yaw_rad());
    // Over the panel the hands keep the last reading (they neither move nor take what is under them),
    // but a Tab pressed there still switches them.
    if (!over_panel) {
        // A press on a stem lying far from its bottom end takes it by that end: the mouse's hand goes
        // there with the press (a device's hand cannot be moved; the panel says to take it there).
        const auto& latest = main_lane.registry.resource<const systems::ReceivedFrames>()->latest();
        const std::uint8_t active = aim_.active_hand();
        hands_.in_scene(in);
        const bool press = hands_.pressed(in);
        in.hand_moves = hands_.last().hand_moves;
        in.hand_to_m = hands_.last().hand_to_m;
        // Pick by ray: an open hand the mouse drives goes, in depth along the cursor's ray, onto the stem
        // drawn under the cursor (the nearest along it), as the cursor moves and with a press. So the
        // yellow stem is the one under the cursor, a press takes it there, and P prunes what the cursor
        // is on, whatever depth the hand had (a wheel notch of 20 mm jumped over a willow; after placing
        // a stem in the kenzan the cube stayed at its depth, far behind the stems on the table). The
        // wheel and Shift still move it in depth, until the cursor next moves.
        if (pointer_ == window_pointer_ && device_names_[active] == "mouse and keyboard") {
            if (const auto there = hand_onto_stem_under_cursor(in, hands_.last(), press, latest, active, camera_.yaw_rad())) {
                in.hand_to_m = *there;
                in.hand_moves += 1;
            }
        }
        if (press && pointer_ == window_pointer_ && device_names_[active] == "mouse and keyboard") {
            const LessonControls* controls = flow_ ? flow_->controls() : nullptr;
            const double along = controls ? controls->grip_along_m(latest, active) : 0.06;
            if (const auto grip = bottom_grip_for(latest, active, along)) {
                const double c = std::cos(-camera_.yaw_rad()), s = std::sin(-camera_.yaw_rad());
                in.hand_to_m = {c * grip->x - s * grip->y, s * grip->x + c * grip->y, grip->z}; // device space: the world turned back by the camera's yaw
                in.hand_moves += 1;
            }
        }
        hands_.give(in);
    } else {
        hands_.over_panel(in);
    }
    shared_pointer_.store(hands_.last());
    keys_ = in;
    keys_.finish_key = keys_.finish_key || act.finish;
    if (act.ghosts) keys_.set_letter(ghost_letter, true);
    if (act.restart) keys_.set_letter(reset_letter, true);
    if (act.report) write_report();
    if (o_.finish_at_frame > 0 && presented_ + 1 == o_.finish_at_frame) keys_.finish_key = true; // a test's Enter
    // As aimed: the cursor where the aim put it (on the hand), and the ray through it.
    read_ = in;
    frame_read_ = true;
}

// The frame's keys, as the lesson (or free practice) takes them; a score is counted and stored.
void TraineeSession::lesson_flow(sched::SystemContext& main_lane) {
    if (!frame_read_ || !flow_) return; // a frame that ended the session
    const auto& latest = main_lane.registry.resource<const systems::ReceivedFrames>()->latest();
    auto& hud = *main_lane.registry.resource<components::HudInfo>();
    const auto out = flow_->update(keys_, mouse_->active_hand(), latest, main_lane.registry.resource<ecs::Port<systems::TraineeChannel>>()->use(), hud,
                                   *main_lane.registry.resource<components::Scenery>());
    if (out.scored) {
        state_.results += 1;
        state_.result_json = out.scored->json(-1);
        stored_.store(*out.scored, latest, hud);
    }
    if (out.restart) {
        restart_.store(true);
        stop_.store(true);
    }
}

// --state-out: the frame as it was read (what a test or a tool drives the window by).
void TraineeSession::write_state(sched::SystemContext& main_lane) {
    // Each frame whose input was read in full (not one that ended the session).
    if (o_.state_out.empty() || !frame_read_) return;
    state_.frame += 1;
    state_.input_read_at_us = std::chrono::duration_cast<std::chrono::microseconds>(read_at_.time_since_epoch()).count();
    state_.window_px = read_.window_px;
    state_.cursor_px = read_.cursor_px;
    take_snapshot(state_, main_lane.registry.resource<const systems::ReceivedFrames>()->latest());
    state_.active_hand = aim_.active_hand();
    state_.px_per_m = glm::dvec2{0.0};
    state_.screen = "lesson";
    state_.buttons.clear();
    for (const auto& b : panel_.buttons()) state_.buttons.push_back({b.label, b.min_px, b.max_px});
    std::vector<WindowState::Box> panels;
    for (const auto& p : panel_.panels()) panels.push_back({p.name, 0, p.min_px, p.size_px});
    take_layout(state_, pointer_view(), window_size_px_, main_lane.registry.resource<const systems::ReceivedFrames>()->latest(), panels);
    if (read_.ray.valid) {
        const auto gain = px_per_m_at(pointer_view(), read_.window_px, read_.ray.eye, state_.hands[state_.active_hand].device_m);
        if (gain) state_.px_per_m = *gain;
    }
    if (auto written = write_window_state(o_.state_out, state_); !written) fail("--state-out: " + written.error().message, 2);
}

// Presents what the prepare phase made of this frame.
void TraineeSession::draw(sched::SystemContext& main_lane) {
    if (stop_.load()) return;
    const auto& prepared = *main_lane.registry.resource<const components::PreparedFrame>();
    // With the panel, no text is drawn over the scene (the G rods' names are the panel's legend).
    renderer_->set_overlay(ui_ ? std::vector<render::OverlayPanel>{} : prepared.overlay);
    const bool want_shot = !o_.screenshot.empty() && o_.frames > 0 && presented_ + 1 >= o_.frames;
    auto presented = stack_->present(prepared.list, camera_.rig(), want_shot);
    if (!presented) return fail(presented.error().message, 3);
    if (!*presented) return; // minimised: nothing to draw, the simulation runs on
    for (const auto& warning : renderer_->take_warnings()) std::cerr << "ikebana: warning: " << warning << "\n";
    auto frame = &**presented;
    if (!frame->presented) return;
    ++presented_;
    timings_.add(frame->timing, read_at_);
    if (frame->screenshot) last_shot_ = std::move(frame->screenshot);
    if (presented_ % 15 == 0) glfwSetWindowTitle(window_->glfw(), status_line(main_lane.registry.resource<const systems::ReceivedFrames>()->latest()).c_str());
    if (o_.frames > 0 && presented_ >= o_.frames) stop_.store(true);
}

// The session's figures (threads' lateness, frame times, validation) are for whoever tunes the app,
// not for the trainee: printed with --stats, else kept in the log file.
void TraineeSession::report_figures(const std::string& figures) const {
    if (o_.stats) {
        std::printf("%s", figures.c_str());
        return;
    }
    if (o_.log_path.empty()) return;
    const std::filesystem::path log(o_.log_path);
    std::error_code ec;
    if (log.has_parent_path()) std::filesystem::create_directories(log.parent_path(), ec);
    if (auto written = assets::write_text_file(log, figures); !written) {
        std::cerr << "ikebana: the session's figures were not logged: " << written.error().message << "\n";
        return;
    }
    std::printf("ikebana: the session's thread and frame figures are in %s (--stats prints them here)\n", o_.log_path.c_str());
}

int TraineeSession::run_and_finish() {
    for (;;) {
        if (showing_start_) {
            const auto chosen = run_start_screen();
            if (!chosen) {
                if (const auto ended = stopped_by_signal(); ended.exit_code != 0) {
                    std::fprintf(stderr, "ikebana: %s\n", ended.why.c_str());
                    code_ = ended.exit_code;
                }
                write_screenshot();
                vkDeviceWaitIdle(ctx_->device());
                return code_;
            }
            if (const int code = load_content(*chosen); code != 0) return code;
            stored_.set_trainee(start_model_.trainee);
            showing_start_ = false;
            if (const int code = enter_content(); code != 0) return code;
            std::printf("ikebana: %s\n", lesson_ ? (lesson_->school + ": " + lesson_->title).c_str() : "free practice");
        }
        const int code = run_once();
        if (code_ != 0) return code;
        stop_.store(false);
        if (back_.exchange(false)) {
            showing_start_ = true;
            continue;
        }
        if (!restart_.exchange(false)) return code;
        // R: the lesson again from the start, in the same window.
        if (const int built = build_world(); built != 0) return built;
        std::printf("ikebana: started over\n");
    }
}

// The start screen, drawn on its own (no world runs behind it): until a lesson is chosen, or Esc,
// the Quit button or the window's close.
std::optional<std::string> TraineeSession::run_start_screen() {
    start_model_.recent = stored_.sessions_of(start_model_.trainee);
    window_pointer_->forget_taps();
    const render::DrawList nothing;
    for (;;) {
        window_->poll_events();
        if (window_->should_close() || stop_requested()) return std::nullopt;
        const platform::PointerState in = window_pointer_->read();
        if (in.quit_key) return std::nullopt;
        renderer_->set_column(0); // the start screen is all panel
        ui_->begin_frame(mode_);
        const std::string before = start_model_.trainee;
        const StartChoice choice = start_screen_.draw(start_model_);
        ui_->end_frame();
        if (start_model_.display != render::stereo_mode_name(mode_)) {
            // Another display chosen: from the next frame, and remembered for the next time.
            const auto chosen = render::parse_stereo_mode(start_model_.display);
            if (chosen) {
                if (auto set = stack_->set_mode(*chosen); !set) {
                    std::cerr << "ikebana: " << set.error().message << "\n";
                    code_ = 3;
                    return std::nullopt;
                }
                mode_ = *chosen;
                stored_.remember("display", start_model_.display);
            }
            start_model_.display = render::stereo_mode_name(mode_);
            state_.display = start_model_.display;
        }
        if (start_model_.trainee != before) start_model_.recent = stored_.sessions_of(start_model_.trainee);
        if (!o_.state_out.empty()) {
            state_.frame += 1;
            state_.input_read_at_us = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
            state_.window_px = in.window_px;
            state_.cursor_px = in.cursor_px;
            state_.screen = "start";
            state_.buttons.clear();
            for (const auto& b : start_screen_.buttons()) state_.buttons.push_back({b.label, b.min_px, b.max_px});
            if (auto written = write_window_state(o_.state_out, state_); !written) {
                std::cerr << "ikebana: --state-out: " << written.error().message << "\n";
                code_ = 2;
                return std::nullopt;
            }
        }
        renderer_->set_overlay({});
        const bool want_shot = !o_.screenshot.empty() && o_.frames > 0 && presented_ + 1 >= o_.frames;
        auto frame = stack_->present(nothing, camera_.base(), want_shot);
        if (!frame) {
            std::cerr << "ikebana: " << frame.error().message << "\n";
            code_ = 3;
            return std::nullopt;
        }
        if (!*frame) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20)); // minimised
        } else {
            if ((*frame)->presented) ++presented_;
            if ((*frame)->screenshot) last_shot_ = std::move((*frame)->screenshot);
        }
        if (choice.kind == StartChoice::Kind::replay) {
            // A past session watched again in this window; Esc or Back comes back here.
            ReplayWindowOptions replay;
            replay.folder = choice.recording;
            replay.state_out = o_.state_out;
            if (const int code = play_recording(*stack_, replay, presented_); code == 3) {
                code_ = 3;
                return std::nullopt;
            }
            window_pointer_->forget_taps();
            continue;
        }
        if (choice.kind == StartChoice::Kind::quit) return std::nullopt;
        if (choice.kind == StartChoice::Kind::lesson) return choice.lesson;
        if (o_.frames > 0 && presented_ >= o_.frames) return std::nullopt;
    }
}

void TraineeSession::write_screenshot() {
    if (o_.screenshot.empty()) return;
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

int TraineeSession::run_once() {
    World& w = *world_;
    std::string figures;
    RunEnding ended;
    // The hands' first reading is the pointer as it is now, not an empty state (that would look like
    // a jump of the cursor from the corner).
    // Presses made while the world was (re)built are dropped here rather than taken by this reading,
    // which no lesson key sees.
    if (pointer_ == window_pointer_) window_pointer_->forget_taps();
    hands_.start(pointer_->read());
    shared_pointer_.store(hands_.last());
    {
        const HandForceWatchdogs watchdogs(w);
        sched::RealtimeConfig config{.max_catchup_us = 50'000, .own_thread_timer_slack_ns = 1'000,
                                     .own_thread_fifo_priority = devices::haptic_lane_fifo_priority,
                                     .lock_memory = true, .on_skip = {}};
        // The simulation's dropped firings go on record, on its own thread (the one that writes the
        // commands file), so that the replay drops the same.
        if (auto* recorder = stored_.recorder()) {
            std::size_t sim_lane = 0;
            for (std::size_t i = 0; i < w.schedule.lanes().size(); ++i) {
                if (w.schedule.lanes()[i].name == "sim") sim_lane = i;
            }
            config.on_skip = [recorder, sim_lane](std::size_t lane, std::int64_t due_us, std::int64_t until_us) {
                if (lane != sim_lane) return;
                char line[64];
                const int n = std::snprintf(line, sizeof line, "%lld,skip,0,%lld\n", static_cast<long long>(due_us), static_cast<long long>(until_us));
                (void)recorder->commands().write(std::string_view(line, static_cast<std::size_t>(n)));
            };
        }
        sched::RealtimeClock clock(w.schedule, config);
        // Until the window closes or the frames asked for are presented.
        const auto lanes = clock.run_for(1e9, &stop_);
        ended = how_the_run_ended(w.schedule, lanes);
        figures += format_realtime_report(w, lanes);
        for (std::size_t hand = 0; hand < 2; ++hand) {
            // Said whatever --stats is: the device's force was cut for safety.
            if (watchdogs.trips(hand) > 0)
                std::fprintf(stderr, "ikebana: %s hand force watchdog: tripped %llu time(s)\n", hand ? "right" : "left",
                             static_cast<unsigned long long>(watchdogs.trips(hand)));
        }
    }
    for (std::size_t hand = 0; hand < 2; ++hand) {
        // Nothing pushes after the session: zero now (a send through the chain would only step down).
        if (w.hand_devices[hand]) (void)w.hand_devices[hand]->zero_force();
    }
    if (ended.exit_code != 0) {
        // Said whatever --stats is: the trainee (or whoever sent the signal) should know why it ended.
        std::fprintf(stderr, "ikebana: %s\n", ended.why.c_str());
        code_ = ended.exit_code;
    }
    // A recording that could not be written whole was said when it happened and as it ended; the status says it too.
    if (!stored_.finish(w, lesson_ ? &*lesson_ : nullptr) && code_ == 0) code_ = 1;
    stored_.store_pending_at_exit();
    write_screenshot();
    char line[600];
    std::snprintf(line, sizeof line, "ikebana: camera turned %.0f deg round, tilted %.0f deg\n", camera_.yaw_rad() * 180.0 / M_PI, camera_.pitch_rad() * 180.0 / M_PI);
    figures += line;
    std::snprintf(line, sizeof line, "ikebana: %u frames presented; %s\n", presented_, status_line(w.main.resource<const systems::ReceivedFrames>()->latest()).c_str());
    figures += line;
    figures += timings_.line();
    if (ctx_->validation_enabled()) {
        std::snprintf(line, sizeof line, "validation: %u errors, %u warnings\n", ctx_->validation_errors(), ctx_->validation_warnings());
        figures += line;
        if (ctx_->validation_errors() > 0 && code_ == 0) code_ = 4;
        if (ctx_->validation_errors() > 0 && !o_.stats) std::fprintf(stderr, "ikebana: %s", line);
    }
    report_figures(figures);
    vkDeviceWaitIdle(ctx_->device());
    return code_;
}

} // namespace

int run_trainee_app(const TraineeAppOptions& o) {
    // Every way out zeroes the devices: Ctrl-C and SIGTERM end the session the ordinary way (the start
    // screen and the clock look for them), a throw on a lane or std::terminate on the spot.
    install_stop_signals();
    install_terminate_handler();
    TraineeSession session(o);
    const int code = session.open();
    return session.is_open() ? session.run_and_finish() : code;
}

} // namespace ikebana::game
