#include "game/app/trainee_app.hpp"

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
#include "game/app/start_screen.hpp"
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

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)))];
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

// The main lane's two systems of the window: input (keys, pointer, camera, Enter) and draw (present
// what prepare_frame_system prepared). They call back into the session that owns the window.
struct WindowInputSystem {
    static constexpr std::string_view name = "window_input";
    static constexpr std::string_view lane = "main";
    static constexpr std::string_view phase = "input";
    static constexpr std::string_view rate = "render"; // frames at the scheduler's render rate (30 Hz by default)
    using reads = sched::Components<systems::ReceivedFrames>;
    // The Ports: the camera's turn goes to the hands' workspace, a cut to the simulation.
    using writes = sched::Components<components::HudInfo, components::Scenery, ecs::Port<systems::ViewChannel>, ecs::Port<systems::TraineeChannel>>;
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
    [[nodiscard]] bool is_open() const noexcept { return opened_; }
    int run_and_finish();
    int run_once();

private:
    void input(sched::SystemContext& main_lane);
    void lesson_keys(const platform::PointerState& in, sched::SystemContext& main_lane);
    void show_result(const std::vector<std::string>& lines, components::HudInfo& hud) const;
    int build_world();
    // The lesson (or the scene) the window shows: loaded, then its hands and world.
    int load_content(const std::string& lesson);
    int enter_content();
    // The start screen until a lesson is chosen (its id) or the trainee leaves (nullopt).
    std::optional<std::string> run_start_screen();
    void write_screenshot();
    void draw(sched::SystemContext& main_lane);
    void fail(const std::string& message, int exit_code);
    [[nodiscard]] std::string frame_times() const;
    void report_figures(const std::string& figures) const;
    void open_progress();
    void store_session(const FormScore& result, const components::FrameSnapshot& frame, components::HudInfo& hud);

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
    LessonPanel panel_;
    bool showing_start_ = false;
    bool opened_ = false;
    std::atomic<bool> back_{false}; // Esc or the panel's button in a lesson: back to the start screen
    platform::PointerSource* pointer_ = nullptr;
    platform::SharedPointerSource shared_pointer_; // GLFW is read here, the hands read it there
    platform::PointerState hands_reading_;         // what the hands were last given
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
    // The trainee's progress: each scored session of a lesson, stored again at each later Enter.
    std::optional<ProgressDb> progress_;
    std::string progress_error_; // why sessions are not stored (said once, and under each result)
    SessionRecord session_;
    std::chrono::steady_clock::time_point session_start_ = std::chrono::steady_clock::now();
    // Each stored session's recording (the hands' samples, cuts, the camera's turns, the clock's
    // skips), for `ikebana replay`: made with the world, finished when it stops, at the last Enter's score.
    std::unique_ptr<SessionRecorder> recorder_;
    std::optional<std::pair<std::int64_t, double>> scored_; // the scored frame's time (us) and the score
    void start_recording();
    void finish_recording();
};

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
    if (!scene) {
        std::cerr << "ikebana: " << scene.error().message << "\n";
        return 2;
    }
    if (auto env = apply_environment_overrides(scene->environment, o_.env); !env) {
        std::cerr << "ikebana: " << env.error().message << "\n";
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
    const std::string stereo = o_.stereo.empty() ? scene_->display.stereo : o_.stereo;
    auto window = platform::Window::create("Ikebana", o_.width, o_.height);
    if (!window) {
        TraineeAppOptions fallback = o_;
        fallback.stereo = stereo;
        return offscreen_instead(fallback, window.error().message);
    }
    auto render_mode = render::parse_stereo_mode(stereo);
    if (!render_mode) {
        std::cerr << "ikebana: " << render_mode.error().message << "\n";
        return 2;
    }
    mode_ = *render_mode;
    auto stack = WindowStack::open(std::move(window).value(), {.width = o_.width, .height = o_.height, .mode = mode_, .validation = o_.validation, .need_ui = showing_start_, .msaa = o_.msaa});
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
    base_rig_ = rig_of(scene_->display);
    open_progress();
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
    base_rig_ = rig_of(scene_->display);
    yaw_ = pitch_ = 0.0;
    aim_ = PointerAim{};
    session_.lesson = lesson_ ? lesson_->id : "";
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
    for (const auto& warning : startup_warnings(*world_)) std::cerr << "ikebana: " << warning << "\n";
    for (std::uint8_t hand = 0; hand < 2; ++hand) world_->attach_device(hand, kept[hand] ? std::move(kept[hand]) : mouse_->hand(hand));
    world_->main.resource<components::HudInfo>()->device = device_names_;
    kenzan_at_ = kenzan_origin(*world_);
    sample_scenery_ = world_->main.resource<components::Scenery>()->list;
    if (lesson_) controls_.emplace(*lesson_, footprint_);
    // A new session (at the start, and after R): stored as a new one at its first Enter.
    start_recording();
    session_.id = 0;
    session_.started_unix_s = static_cast<std::int64_t>(std::time(nullptr));
    session_start_ = std::chrono::steady_clock::now();
    return 0;
}

// The progress database, when sessions are stored and this is a lesson scored against its form. A
// database that cannot be used is said, and the lesson goes on without storing: a damaged file is
// never written to.
void TraineeSession::open_progress() {
    if (o_.progress_db.empty()) return;
    if (!showing_start_ && !lesson_) return;
    auto db = ProgressDb::open(o_.progress_db);
    if (!db) {
        progress_error_ = db.error().message;
        std::cerr << "ikebana: sessions will not be stored: " << progress_error_ << "\n";
        start_model_.progress_note = "Results are not kept: " + progress_error_;
        return;
    }
    start_model_.progress_note = "Results are kept in " + o_.progress_db;
    progress_.emplace(std::move(db).value());
    std::string trainee = o_.trainee;
    if (trainee.empty()) {
        if (auto remembered = progress_->setting("trainee"); remembered && *remembered) trainee = **remembered;
    } else if (auto kept = progress_->set_setting("trainee", trainee); !kept) {
        std::cerr << "ikebana: the trainee's name is not remembered: " << kept.error().message << "\n";
    }
    if (trainee.empty()) {
        const char* user = std::getenv("USER");
        trainee = user && *user ? user : "trainee";
    }
    session_.trainee = o_.demonstration ? "teacher" : trainee;
    session_.kind = o_.demonstration ? "demonstration" : "practice";
    session_.lesson = lesson_ ? lesson_->id : "";
    start_model_.trainee = trainee;
}

// A stored session is recorded: in a folder of its own beside the progress database.
void TraineeSession::start_recording() {
    recorder_.reset();
    scored_.reset();
    session_.recording.clear();
    if (!progress_ || !lesson_ || !world_) return;
    const auto now = static_cast<std::int64_t>(std::time(nullptr));
    std::string stamp = iso_utc(now);
    std::replace(stamp.begin(), stamp.end(), ':', '-');
    const auto parent = std::filesystem::path(o_.progress_db).parent_path() / "recordings";
    std::filesystem::path folder = parent / (stamp + "-" + lesson_->id);
    std::error_code ec;
    for (int n = 2; std::filesystem::exists(folder, ec) && n < 100; ++n) folder = parent / (stamp + "-" + lesson_->id + "-" + std::to_string(n));
    std::filesystem::create_directories(parent, ec);
    auto recorder = SessionRecorder::create(folder, /*real_time=*/true);
    if (!recorder) {
        std::cerr << "ikebana: the session is not recorded: " << recorder.error().message << "\n";
        return;
    }
    recorder_ = std::move(recorder).value();
    recorder_->attach(*world_);
    session_.recording = std::filesystem::absolute(folder).string();
}

// When the world has stopped: session.json with the last Enter's score, or no recording at all when
// nothing was scored (no stored session points at it).
void TraineeSession::finish_recording() {
    if (!recorder_) return;
    World& w = *world_;
    recorder_->detach(w);
    std::int64_t end_us = std::numeric_limits<std::int64_t>::max();
    for (const auto& s : w.schedule.systems()) {
        if (w.schedule.lanes()[s.lane].name == "sim") end_us = std::min(end_us, s.next_due_us);
    }
    const auto folder = recorder_->folder();
    if (scored_ && scored_->first < end_us) {
        SessionRecorder::WindowRun run;
        run.scored_frame_us = scored_->first;
        run.rates = o_.rates;
        run.env = o_.env;
        for (std::size_t h = 0; h < 2; ++h) run.rate_device[h] = w.hand_devices[h] && !w.hand_devices[h]->capabilities().reports_position;
        if (auto done = recorder_->finish_window(*lesson_, session_.kind, run, end_us, scored_->second, w); !done)
            std::cerr << "ikebana: the session's recording is incomplete: " << done.error().message << "\n";
        recorder_.reset();
        return;
    }
    recorder_.reset();
    std::error_code ec;
    std::filesystem::remove_all(folder, ec);
}

// Each Enter stores the session as it now stands (the first adds it, later ones replace it).
void TraineeSession::store_session(const FormScore& result, const components::FrameSnapshot& frame, components::HudInfo& hud) {
    if (!progress_error_.empty()) {
        hud.result.push_back("not stored: " + progress_error_.substr(0, 60));
        return;
    }
    if (!progress_ || session_.lesson.empty()) return;
    session_.result = result;
    session_.flowers = flower_outcomes(frame);
    session_.duration_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - session_start_).count();
    if (auto saved = progress_->save(session_); !saved) {
        std::cerr << "ikebana: the session was not stored: " << saved.error().message << "\n";
        hud.result.push_back("not stored (see the terminal)");
        return;
    }
    // The recording ends at this score: the frame it was taken from, when one had come (an Enter
    // before the first frame scores nothing the simulation published).
    if (recorder_ && !frame.flowers.empty()) scored_ = std::make_pair(frame.sim_time_us, result.score);
    std::printf("ikebana: stored as session %lld in %s\n", static_cast<long long>(session_.id), progress_->path().c_str());
    std::fflush(stdout);
}

// Keys, pointer and camera; Enter scores the arrangement (the result stays on screen, the session goes on).
void TraineeSession::input(sched::SystemContext& main_lane) {
    if (stop_.load()) return;
    if (o_.each_frame) o_.each_frame(presented_, window_->glfw());
    window_->poll_events();
    platform::PointerState in = pointer_->read();
    const auto read_at = std::chrono::steady_clock::now();
    // The lesson's panel: its buttons do what the keys do.
    LessonPanelActions act;
    if (ui_ && lesson_) {
        ui_->begin_frame(mode_);
        act = panel_.draw({lesson_->school + ": " + lesson_->title, session_.trainee, {}, controls_ && controls_->ghosts()});
        ui_->end_frame();
    }
    const bool over_panel = ui_ && lesson_ && ui_->wants_pointer();
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
    main_lane.registry.resource<ecs::Port<systems::ViewChannel>>()->use().yaw_rad.store(yaw_, std::memory_order_relaxed);
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
    // Over the panel the hands keep the last reading (they neither move nor take what is under them),
    // but a Tab pressed there still switches them.
    if (!over_panel) {
        hands_reading_ = in;
    } else {
        hands_reading_.switch_hand = in.switch_hand;
        hands_reading_.ray_before = hands_reading_.ray;
        hands_reading_.warped_from_px = glm::dvec2{-1.0};
    }
    shared_pointer_.store(hands_reading_);
    platform::PointerState keys = in;
    keys.finish_key = keys.finish_key || act.finish;
    if (act.ghosts) keys.set_letter(ghost_letter, true);
    if (act.restart) keys.set_letter(reset_letter, true);
    if (o_.finish_at_frame > 0 && presented_ + 1 == o_.finish_at_frame) keys.finish_key = true; // a test's Enter
    if (lesson_) lesson_keys(keys, main_lane); // a form lesson's Enter is scored there
    const bool form = lesson_ && lesson_->scoring == "form";
    if (!form && keys.finish_key && !enter_was_down_) {
        const auto& latest = main_lane.registry.resource<const systems::ReceivedFrames>()->latest();
        auto& hud = *main_lane.registry.resource<components::HudInfo>();
        if (lesson_ && !scene_->sample.empty()) {
            // The free-practice lesson: scored as `lesson score` scores it, and stored like a form's.
            const FormScore result = score_sample(*lesson_, measure_arrangement(latest), scene_->sample);
            state_.results += 1;
            state_.result_json = result.json(-1);
            show_result(result.lines(), hud);
            store_session(result, latest, hud);
        } else {
            const auto result = score_arrangement(arranged_stems(latest), scene_->sample, kenzan_at_);
            show_result(scene_->sample.empty() ? std::vector<std::string>{"RESULT: free practice (this scene has no sample)"} : result.lines(), hud);
        }
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
        state_.screen = "lesson";
        state_.buttons.clear();
        for (const auto& b : panel_.buttons()) state_.buttons.push_back({b.label, b.min_px, b.max_px});
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
    const auto effects = controls_->update(in, mouse_->active_hand(), latest, main_lane.registry.resource<ecs::Port<systems::TraineeChannel>>()->use());
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
    if (effects.score && effects.score->ok()) store_session(**effects.score, latest, hud);
    if (effects.restart) {
        restart_.store(true);
        stop_.store(true);
    }
}

// Presents what the prepare phase made of this frame.
void TraineeSession::draw(sched::SystemContext& main_lane) {
    if (stop_.load()) return;
    const auto& prepared = *main_lane.registry.resource<const components::PreparedFrame>();
    renderer_->set_overlay(prepared.overlay);
    const bool want_shot = !o_.screenshot.empty() && o_.frames > 0 && presented_ + 1 >= o_.frames;
    auto presented = stack_->present(prepared.list, render::orbited(base_rig_, yaw_, pitch_), want_shot);
    if (!presented) return fail(presented.error().message, 3);
    if (!*presented) return; // minimised: nothing to draw, the simulation runs on
    for (const auto& warning : renderer_->take_warnings()) std::cerr << "ikebana: warning: " << warning << "\n";
    auto frame = &**presented;
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

std::string TraineeSession::frame_times() const {
    if (frame_ms_.size() <= 2) return {};
    auto whole = frame_ms_;
    whole.erase(whole.begin()); // the first frame includes start-up
    char line[400];
    std::snprintf(line, sizeof line, "frame time, ms (p50 / p95): whole frame %.1f / %.1f; record %.2f / %.2f; device: shadow %.1f / %.1f, both eyes %.1f / %.1f, "
                "composite and HUD %.1f / %.1f; present %.2f / %.2f\n",
                percentile(whole, 0.5), percentile(whole, 0.95), percentile(record_ms_, 0.5), percentile(record_ms_, 0.95),
                percentile(shadow_ms_, 0.5), percentile(shadow_ms_, 0.95), percentile(eyes_ms_, 0.5), percentile(eyes_ms_, 0.95),
                percentile(composite_ms_, 0.5), percentile(composite_ms_, 0.95), percentile(present_ms_, 0.5), percentile(present_ms_, 0.95));
    return line;
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
                write_screenshot();
                vkDeviceWaitIdle(ctx_->device());
                return code_;
            }
            if (const int code = load_content(*chosen); code != 0) return code;
            if (progress_ && !o_.demonstration) {
                if (auto kept = progress_->set_setting("trainee", start_model_.trainee); !kept)
                    std::cerr << "ikebana: the trainee's name is not remembered: " << kept.error().message << "\n";
                session_.trainee = start_model_.trainee;
            }
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
    if (progress_) {
        auto mine = progress_->sessions({start_model_.trainee, ""});
        if (mine) start_model_.recent = std::move(mine).value();
    }
    window_pointer_->forget_taps();
    const render::DrawList nothing;
    for (;;) {
        window_->poll_events();
        if (window_->should_close()) return std::nullopt;
        const platform::PointerState in = window_pointer_->read();
        if (in.quit_key) return std::nullopt;
        ui_->begin_frame(mode_);
        const std::string before = start_model_.trainee;
        const StartChoice choice = start_screen_.draw(start_model_);
        ui_->end_frame();
        if (start_model_.trainee != before && progress_) {
            auto mine = progress_->sessions({start_model_.trainee, ""});
            start_model_.recent = mine ? std::move(mine).value() : std::vector<SessionRecord>{};
        }
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
        auto frame = stack_->present(nothing, base_rig_, want_shot);
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
    // The hands' first reading is the pointer as it is now, not an empty state (that would look like
    // a jump of the cursor from the corner).
    // Presses made while the world was (re)built are dropped here rather than taken by this reading,
    // which no lesson key sees.
    if (pointer_ == window_pointer_) window_pointer_->forget_taps();
    hands_reading_ = pointer_->read();
    shared_pointer_.store(hands_reading_);
    {
        const HandForceWatchdogs watchdogs(w);
        sched::RealtimeConfig config{.max_catchup_us = 50'000, .own_thread_timer_slack_ns = 1'000, .own_thread_fifo_priority = 20, .on_skip = {}};
        // The simulation's dropped firings go on record, on its own thread (the one that writes the
        // commands file), so that the replay drops the same.
        if (recorder_) {
            std::size_t sim_lane = 0;
            for (std::size_t i = 0; i < w.schedule.lanes().size(); ++i) {
                if (w.schedule.lanes()[i].name == "sim") sim_lane = i;
            }
            config.on_skip = [this, sim_lane](std::size_t lane, std::int64_t due_us, std::int64_t until_us) {
                if (lane != sim_lane) return;
                char line[64];
                const int n = std::snprintf(line, sizeof line, "%lld,skip,0,%lld\n", static_cast<long long>(due_us), static_cast<long long>(until_us));
                (void)recorder_->commands().write(std::string_view(line, static_cast<std::size_t>(n)));
            };
        }
        sched::RealtimeClock clock(w.schedule, config);
        // Until the window closes or the frames asked for are presented.
        const auto lanes = clock.run_for(1e9, &stop_);
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
    finish_recording();
    write_screenshot();
    char line[600];
    std::snprintf(line, sizeof line, "ikebana: camera turned %.0f deg round, tilted %.0f deg\n", yaw_ * 180.0 / M_PI, pitch_ * 180.0 / M_PI);
    figures += line;
    std::snprintf(line, sizeof line, "ikebana: %u frames presented; %s\n", presented_, status_line(w.main.resource<const systems::ReceivedFrames>()->latest()).c_str());
    figures += line;
    figures += frame_times();
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
    TraineeSession session(o);
    const int code = session.open();
    return session.is_open() ? session.run_and_finish() : code;
}

} // namespace ikebana::game
