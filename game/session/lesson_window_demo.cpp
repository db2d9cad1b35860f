// The demonstration in the window: the trainee app runs as it does for a trainee, and the teacher
// works it from outside with the X pointer and keyboard (xdotool), reading what the window shows
// from its --state-out file as a person reads the screen. Nothing reaches the simulation but the
// mouse and the keys; the window scores the arrangement on Enter.
//
// Every motion waits until the window has read it (its state says when it last read input): the
// window reads the mouse once a frame, a few frames a second on lavapipe under Xvfb, and a modifier
// or a key must be down while a frame reads it.
#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <thread>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "game/session/lesson_controls.hpp"
#include "game/session/lesson_demo.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/session/teacher.hpp"
#include "game/session/window_state.hpp"
#include "game/species/species.hpp"

extern char** environ;

namespace ikebana::game {

namespace {

// `xdotool COMMANDS` (words split at spaces, as the shell did), its output to /dev/null; true when it
// exits 0. Spawned and waited for, not std::system: system() ignores SIGINT while its child runs,
// and the demonstration runs xdotool all the time, so Ctrl-C did not stop it.
bool run_xdotool(const std::string& commands) {
    std::vector<std::string> words{"xdotool"};
    std::size_t from = 0;
    while (from < commands.size()) {
        const std::size_t to = std::min(commands.find(' ', from), commands.size());
        if (to > from) words.push_back(commands.substr(from, to - from));
        from = to + 1;
    }
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = -1;
    const int spawned = posix_spawnp(&pid, "xdotool", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) return false;
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) return false;
    }
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

} // namespace

namespace {

std::int64_t steady_us() {
    return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool on_path(const std::string& program) {
    const char* path = std::getenv("PATH");
    if (!path) return false;
    std::string dirs = path;
    std::size_t from = 0;
    while (from <= dirs.size()) {
        const std::size_t to = std::min(dirs.find(':', from), dirs.size());
        const auto candidate = std::filesystem::path(dirs.substr(from, to - from)) / program;
        if (::access(candidate.c_str(), X_OK) == 0) return true;
        from = to + 1;
    }
    return false;
}

// The window in its own process, worked through X.
class WindowSession final : public Classroom, public TeacherHand {
public:
    WindowSession(std::filesystem::path state, std::filesystem::path log, pid_t app)
        : state_path_(std::move(state)), log_path_(std::move(log)), app_(app), config_(lesson_mouse_config()) {}
    ~WindowSession() override {
        if (app_ > 0) {
            ::kill(app_, SIGTERM);
            ::waitpid(app_, nullptr, 0);
        }
    }
    WindowSession(const WindowSession&) = delete;
    WindowSession& operator=(const WindowSession&) = delete;

    [[nodiscard]] const std::string& failure() const { return failure_; }
    [[nodiscard]] const WindowState& state() const { return state_; }

    // Until the window has shown its first frame; the hand starts where the window put it.
    bool start(double timeout_s) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
        while (!refresh() || state_.frame < 3) {
            if (!failure_.empty()) return false;
            if (std::chrono::steady_clock::now() > until) return fail("the window showed no frame in " + std::to_string(static_cast<int>(timeout_s)) + " s");
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        started_ = std::chrono::steady_clock::now();
        // The window has put the cursor on the hand; wait until it shows so.
        seen(steady_us());
        for (std::uint8_t h = 0; h < 2; ++h) position_[h] = state_.hands[h].device_m;
        active_ = state_.active_hand & 1u;
        cursor_ = state_.cursor_px;
        return true;
    }

    // Classroom: what the window's state shows.
    double now_s() const override { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count(); }
    void wait(double seconds) override {
        if (!failure_.empty()) return;
        std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
        // A moving hand's short waits only take the newest state; a teacher's pause waits until the
        // window shows what happened.
        if (seconds >= 0.1) seen(steady_us());
        else refresh();
    }
    std::size_t flower_count() const override { return state_.flowers.size(); }
    SeenFlower flower(std::size_t i) const override {
        SeenFlower f;
        if (i >= state_.flowers.size()) return f;
        const auto& s = state_.flowers[i];
        f.species = s.species;
        f.points_m = s.points_m;
        for (std::size_t k = 1; k < s.points_m.size(); ++k) f.length_m += glm::length(s.points_m[k] - s.points_m[k - 1]);
        f.diameter_m = s.diameter_m;
        f.in_kenzan = s.in_kenzan;
        f.fallen = s.fallen;
        f.fall_reason = s.fall_reason;
        f.yield_holding_nm = s.yield_holding_nm;
        f.yield_gravity_nm = s.yield_gravity_nm;
        f.pins = s.pins_engaged;
        f.depth_m = s.depth_m;
        // How far it springs back from a bend, as a teacher knows the material (the species' file).
        auto known = species_.find(s.species);
        if (known == species_.end()) {
            auto def = load_species(s.species);
            known = species_.emplace(s.species, def ? def->permanent_set_rad : 0.0).first;
        }
        f.keeps_bend_beyond_rad = known->second;
        return f;
    }
    std::optional<std::size_t> held(std::uint8_t hand) const override {
        const auto held = state_.hands[hand & 1u].held_flower;
        return held >= 0 ? std::optional<std::size_t>(static_cast<std::size_t>(held)) : std::nullopt;
    }
    glm::dvec3 hand_at(std::uint8_t hand) const override { return state_.hands[hand & 1u].position_m; }
    glm::dvec3 kenzan_origin_m() const override { return state_.kenzan_origin_m.value_or(glm::dvec3{0.0}); }
    double pin_height_m() const override { return state_.kenzan_pin_height_m; }

    // TeacherHand: the X pointer. Where the hand is, as this session has moved it (the window
    // follows every pixel); look() takes it from the window again before each stem.
    glm::dvec3 position() const override { return position_[active_]; }
    glm::dvec3 angles() const override { return angles_[active_]; }
    // Tab, as a trainee presses it: the mouse drives the other hand (the window puts the cursor on it,
    // and the button as it is goes with it).
    bool two_hands() const override { return true; }
    bool turns_freely() const override { return false; }
    bool use(std::uint8_t hand) override {
        hand &= 1u;
        if (hand == active_) return true;
        press_key("Tab");
        if ((state_.active_hand & 1u) != hand) return fail("Tab did not hand the mouse to the other hand");
        active_ = hand;
        position_[hand] = state_.hands[hand].device_m;
        return true;
    }
    // Small steps, about one a frame: a held stem swung in frame-sized jumps of centimetres hits
    // the pins on its way. Turns are read a quarter second apart (Ctrl must be seen down each time).
    double step_s() const override { return 0.05; }
    double step_m() const override { return 0.01; }
    double turn_step_s() const override { return 0.2; }
    void look() override {
        if (!state_.hands[active_].holding) position_[active_] = state_.hands[active_].device_m;
    }
    void go(glm::dvec3 target) override {
        // How far the cursor moves for a metre of the hand, where the hand is now (the window aims the
        // cursor through its camera: nearer things move further on screen); without aiming, the
        // window's size spans the workspace.
        const glm::dvec2 px_per_m = state_.px_per_m.x > 0.0 && state_.px_per_m.y > 0.0
                                        ? state_.px_per_m
                                        : glm::dvec2{state_.window_px.x / config_.workspace_width_m, state_.window_px.y / config_.workspace_height_m};
        glm::dvec3& at = position_[active_];
        const glm::dvec3 d = glm::clamp(target, config_.reach_min_m, config_.reach_max_m) - at;
        const int x = static_cast<int>(std::lround(d.x * px_per_m.x));
        const int up = static_cast<int>(std::lround(d.z * px_per_m.y));
        const int away = static_cast<int>(std::lround(d.y * px_per_m.y));
        at.x += x / px_per_m.x;
        at.z += up / px_per_m.y;
        at.y += away / px_per_m.y;
        if (x != 0 || up != 0) move_pointer(x, -up);
        if (away != 0) held_down("shift", [&] { move_pointer(0, -away); });
    }
    // Holding nothing: Ctrl+drag sideways, then up or down, then the wheel, each seen by the window
    // before the next: turns about one axis each, which add up to the turn asked for however the window
    // reads them. Holding a stem: Ctrl+Shift+drag to twist it about its own axis, seen, then one
    // Ctrl+drag that takes its tip where the turn puts it (the window leans a held stem the way the
    // drag goes: lean_turn).
    void turn(glm::dvec3 target) override {
        glm::dvec3& turned = angles_[active_];
        const auto g = devices::MouseKeyboardHands::tilt_gesture(config_, turned, target, held_along());
        if (g.clicks == 0 && g.right_px == 0 && g.down_px == 0 && g.twist_px == 0) return;
        turned = g.reached;
        if (g.held) {
            if (g.twist_px != 0) held_down("ctrl+shift", [&] { move_pointer(g.twist_px, 0); });
            if (g.right_px != 0 || g.down_px != 0) held_down("ctrl", [&] { move_pointer(g.right_px, g.down_px); });
            return;
        }
        std::string wheel;
        for (int c = 0; c < std::abs(g.clicks); ++c) wheel += std::string(g.clicks > 0 ? "click 4 " : "click 5 ") + "sleep 0.02 ";
        held_down("ctrl", [&] {
            move_pointer(g.right_px, 0);
            if (g.right_px != 0 && g.down_px != 0) seen(steady_us());
            move_pointer(0, g.down_px);
            if (g.down_px != 0 && g.clicks != 0) seen(steady_us());
            xdo(wheel);
        });
    }
    // Which way the stem the active hand holds points, bottom to tip, as the window tells its hands
    // (device space: this demonstration never turns the camera); nothing when it holds none.
    std::optional<glm::dvec3> held_along() const {
        const auto& hand = state_.hands[active_];
        if (!hand.holding || hand.held_flower < 0 || static_cast<std::size_t>(hand.held_flower) >= state_.flowers.size()) return std::nullopt;
        const auto& points = state_.flowers[static_cast<std::size_t>(hand.held_flower)].points_m;
        if (points.size() < 2 || glm::length(points.back() - points.front()) < 1e-6) return std::nullopt;
        return glm::normalize(points.back() - points.front());
    }
    void grab(bool down) override {
        xdo(down ? "mousedown 1" : "mouseup 1");
        seen(steady_us());
    }
    void cut(double) override { press_key("c"); }
    void prune() override { press_key("p"); }

    void press_key(const std::string& key) {
        xdo("keydown " + key);
        seen(steady_us());
        xdo("keyup " + key);
        seen(steady_us());
    }
    // Enter, and the window's result.
    bool finish(double timeout_s) {
        const auto before = state_.results;
        press_key("Return");
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
        while (failure_.empty() && state_.results == before) {
            if (std::chrono::steady_clock::now() > until) return fail("Enter showed no result");
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            refresh();
        }
        return failure_.empty();
    }
    // Escape; the window closes and the app ends.
    void close(double timeout_s) {
        if (app_ <= 0) return;
        xdo("keydown Escape sleep 0.5 keyup Escape");
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
        while (std::chrono::steady_clock::now() < until) {
            if (::waitpid(app_, nullptr, WNOHANG) == app_) {
                app_ = -1;
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
    }

private:
    bool fail(const std::string& why) {
        if (failure_.empty()) {
            failure_ = why;
            auto log = assets::read_text_file(log_path_);
            if (log && !log->empty()) failure_ += " (the window's log, " + log_path_.string() + ", ends: " + log->substr(log->size() > 400 ? log->size() - 400 : 0) + ")";
        }
        return false;
    }
    // The newest state the window wrote; false while there is none or the app has ended.
    bool refresh() {
        if (app_ > 0 && ::waitpid(app_, nullptr, WNOHANG) == app_) {
            app_ = -1;
            return fail("the window closed during the demonstration");
        }
        auto text = assets::read_text_file(state_path_);
        if (!text) return false;
        auto parsed = parse_window_state(*text, state_path_.string());
        if (!parsed) return false;
        state_ = std::move(parsed).value();
        // What the trainee sees is checked as the demonstration goes: no panel over the scene.
        if (const auto over = panel_over_scene(state_)) return fail("frame " + std::to_string(state_.frame) + ": " + *over);
        return true;
    }
    // Until the window has read its input after `t_us`, and two frames more: the simulation has then
    // taken it and the snapshot shows what it did.
    void seen(std::int64_t t_us) {
        motion_unseen_ = false;
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        std::uint64_t read_in = 0;
        while (failure_.empty()) {
            if (refresh()) {
                if (read_in == 0 && state_.input_read_at_us > t_us) read_in = state_.frame;
                if (read_in != 0 && state_.frame >= read_in + 2) {
                    cursor_ = state_.cursor_px; // all motion sent before t_us has been read (and put back in the middle at an edge)
                    return;
                }
            }
            if (std::chrono::steady_clock::now() > until) {
                fail("the window read no input for 30 s");
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    // A modifier held while the window reads the motion made under it.
    template <typename Motion>
    void held_down(const std::string& key, Motion&& motion) {
        // Plain motion not yet read would be read with the modifier down (up-down as depth, or a tilt).
        if (motion_unseen_) seen(steady_us());
        xdo("keydown " + key);
        seen(steady_us());
        motion();
        if (motion_unseen_) seen(steady_us());
        xdo("keyup " + key);
        seen(steady_us());
    }
    // Relative motion, at most 4 pixels a piece (the X server doubles a relative motion beyond its
    // threshold). The cursor must stay in the window: past its edge the screen's edge stops it and the
    // motion is lost (the window sits at the screen's top left). During a Ctrl+drag the window puts a
    // cursor that comes within 24 px of its edge back in the middle of its eye's image when it reads
    // it; so the motion stops 14-18 px from an edge until the window has read it there, then goes on
    // from where the window shows the cursor. (Plain motion keeps the hand under the cursor, and the
    // lesson's places are all in view.)
    void move_pointer(int x, int y) {
        const int n = std::max(1, (std::max(std::abs(x), std::abs(y)) + 3) / 4);
        int done_x = 0, done_y = 0;
        std::string batch;
        const auto send = [&] {
            xdo(batch);
            batch.clear();
            motion_unseen_ = true;
        };
        for (int i = 1; i <= n; ++i) {
            const int px = static_cast<int>(std::lround(static_cast<double>(x) * i / n)) - done_x;
            const int py = static_cast<int>(std::lround(static_cast<double>(y) * i / n)) - done_y;
            const glm::dvec2 next = cursor_ + glm::dvec2(px, py);
            // The scene's edges (the panels' column is beside it), else the window's.
            glm::dvec2 lo{0.0}, hi = state_.window_px;
            for (const auto& v : state_.layout.views) {
                if (cursor_.x >= v.min_px.x && cursor_.x < v.min_px.x + v.size_px.x) {
                    lo = v.min_px;
                    hi = v.min_px + v.size_px;
                }
            }
            if (next.x < lo.x + 14.0 || next.y < lo.y + 14.0 || next.x > hi.x - 14.0 || next.y > hi.y - 14.0) {
                if (!batch.empty()) send();
                seen(steady_us()); // the window reads it at its edge and puts it back in the middle
                if (!failure_.empty()) return;
            }
            done_x += px;
            done_y += py;
            cursor_ += glm::dvec2(px, py);
            if (px != 0 || py != 0) batch += "mousemove_relative -- " + std::to_string(px) + " " + std::to_string(py) + " sleep 0.004 ";
        }
        if (!batch.empty()) send();
    }
    void xdo(const std::string& commands) {
        if (!failure_.empty() || commands.empty()) return;
        if (!run_xdotool(commands)) fail("xdotool refused: " + commands.substr(0, 80));
    }

    std::filesystem::path state_path_, log_path_;
    pid_t app_;
    devices::MouseKeyboardHands::Config config_;
    WindowState state_;
    std::string failure_;
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
    std::array<glm::dvec3, 2> position_{}, angles_{}; // each hand's, as moved from here
    std::uint8_t active_ = 1;                         // the hand the mouse drives
    mutable std::map<std::string, double> species_;   // permanent set, by species (read once)
    bool motion_unseen_ = false; // plain motion sent since the window last showed it had read input
    glm::dvec2 cursor_{0.0};     // where the cursor is in the window, with the motion sent since
};

} // namespace

Result<DemoResult> run_lesson_demo_in_window(const LessonDef& lesson, const DemoOptions& options) {
    if (lesson.scoring != "form") return make_error(ErrorCode::invalid_argument, lesson.id + " copies its scene's sample; it has no form to demonstrate");
    const auto footprint = footprint_of(lesson);
    if (!footprint) return std::move(footprint).error();
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display) return make_error(ErrorCode::device_error, "--window: no X display (DISPLAY is not set); without --window the demonstration runs headless");
    if (!on_path("xdotool")) return make_error(ErrorCode::not_found, "--window: xdotool is not installed (Debian: apt install xdotool); it moves the X pointer");
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return make_error(ErrorCode::io_error, "--window: cannot find this program (/proc/self/exe): " + ec.message());
    const auto folder = std::filesystem::temp_directory_path() / ("ikebana-demo-" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder, ec);
    if (ec) return make_error(ErrorCode::io_error, "--window: cannot make " + folder.string() + ": " + ec.message());
    const auto state = folder / "state.json", log = folder / "window.log";
    std::filesystem::remove(state, ec);
    // The window opens at the screen's corner (no window manager under Xvfb): the pointer starts in
    // its middle, where a trainee's hand would be. A first-time trainee's screen: flat, 1280x720, the
    // panel beside the scene.
    constexpr int width = 1280, height = 720;
    if (!run_xdotool("mousemove " + std::to_string(width / 2) + " " + std::to_string(height / 2))) return make_error(ErrorCode::device_error, std::string("--window: xdotool cannot move the pointer on display ") + display);
    std::vector<std::string> args{self.string(), "--lesson", lesson.file.empty() ? lesson.id : lesson.file.string(), "--width", std::to_string(width),
                                        "--height", std::to_string(height), "--stereo", "mono", "--state-out", state.string()};
    if (options.window_progress_db.empty()) {
        args.push_back("--no-history");
    } else {
        args.insert(args.end(), {"--db", options.window_progress_db, "--demonstration"});
    }
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = -1;
    const int spawned = posix_spawn(&pid, self.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) return make_error(ErrorCode::io_error, "--window: cannot start the window: " + std::string(std::strerror(spawned)));

    WindowSession window(state, log, pid);
    if (options.window_started) options.window_started(pid);
    DemoResult result;
    if (window.start(60.0)) teach(lesson, model_arrangement(lesson, *footprint), window, window, result, options);
    if (window.failure().empty()) window.finish(20.0);
    if (!window.failure().empty()) return make_error(ErrorCode::device_error, "--window: " + window.failure());
    const std::string shown = window.state().result_json;
    result.simulated_s = static_cast<double>(window.state().sim_time_us) * 1e-6;
    window.close(30.0);
    std::filesystem::remove_all(folder, ec); // kept when something went wrong: the error names its log
    // The window's own result, scored again here from its arrangement: the same function of the same
    // numbers (rounded as the JSON has them), so the two agree to the rounding.
    auto arrangement = parse_arrangement(shown, "the window's result");
    if (!arrangement) return std::move(arrangement).error();
    auto scored = score_form(lesson, *arrangement, *footprint, "the window's result");
    if (!scored) return std::move(scored).error();
    const double window_score = nlohmann::json::parse(shown, nullptr, false).value("score", -1.0);
    if (std::abs(window_score - scored->score) > 1.0)
        return make_error(ErrorCode::invalid_argument, "--window: the window scored " + std::to_string(window_score) + ", its arrangement scores " + std::to_string(scored->score));
    result.score = std::move(scored).value();
    return result;
}

} // namespace ikebana::game
