#include "game/session/lesson_demo.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>

#include <glm/gtc/quaternion.hpp>

#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/flower.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "engine/assets/files.hpp"
#include "engine/devices/device_angles.hpp"
#include "engine/devices/mouse_keyboard_device.hpp"
#include "engine/ecs/hierarchy.hpp"
#include "engine/sched/clocks.hpp"
#include "game/render/pointer_aim.hpp"
#include "game/render/offscreen_render.hpp"
#include "game/session/lesson_controls.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/session/lesson_session.hpp"
#include "game/session/teacher.hpp"
#include "game/world/world.hpp"
#include "systems/haptics/grab_system.hpp"
#include "systems/insertion/pruning_system.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::game {

using namespace components;

PuppetDevice::PuppetDevice(std::shared_ptr<Pose> pose) : pose_(std::move(pose)) {
    caps_.name = "the teacher's hand (scripted)";
    caps_.reports_position = true;
    caps_.on_timeline = true;
    caps_.workspace_half_extent_m = glm::dvec3{1.0};
}

Result<devices::DeviceSample> PuppetDevice::poll(std::int64_t now_us) {
    devices::DeviceSample s;
    s.time_us = now_us;
    s.position = pose_->position_m;
    s.rotation = pose_->rotation_rad;
    s.buttons = pose_->buttons;
    return s;
}

namespace {

// Two puppet devices, one for each hand.
class PuppetHand final : public TeacherHand {
public:
    PuppetHand(std::array<std::shared_ptr<PuppetDevice::Pose>, 2> poses, World& world) : poses_(std::move(poses)), w_(world) {}
    glm::dvec3 position() const override { return poses_[using_]->position_m; }
    glm::dvec3 angles() const override { return poses_[using_]->rotation_rad; }
    void go(glm::dvec3 position_m) override { poses_[using_]->position_m = position_m; }
    void turn(glm::dvec3 angles_rad) override { poses_[using_]->rotation_rad = angles_rad; }
    void grab(bool down) override { poses_[using_]->buttons = down ? 1u : 0u; }
    void cut(double keep_m) override { (void)w_.trainee.push({systems::TraineeCommand::Kind::cut, static_cast<std::uint8_t>(using_), keep_m}); }
    void prune() override { (void)w_.trainee.push({systems::TraineeCommand::Kind::prune, static_cast<std::uint8_t>(using_), 0.0}); }
    bool use(std::uint8_t hand) override {
        using_ = hand & 1u;
        return true;
    }
    bool two_hands() const override { return true; }

private:
    std::array<std::shared_ptr<PuppetDevice::Pose>, 2> poses_;
    std::size_t using_ = 1;
    World& w_;
};

// A pointer the script sets, read by the same MouseKeyboardHands and LessonControls as the window's.
struct ScriptedPointer final : platform::PointerSource {
    platform::PointerState state = [] {
        platform::PointerState s;
        s.window_px = {1200.0, 675.0};
        s.cursor_px = 0.5 * s.window_px;
        return s;
    }();
    platform::PointerState read() override { return state; }
};

// The mouse session as an xdotool script, to replay against the window under X: motion gathered
// into seconds (plain, then with Shift, then with Ctrl and Shift, then with Ctrl, each modifier held over whole frames so
// that the window reads it with its motion), buttons and keys in order, and sleeps that keep the
// script's time with the simulation's.
class XdoScript {
public:
    explicit XdoScript(std::string path) : path_(std::move(path)) {
        // The cursor must be in the window's middle before the window opens (a jump once it reads the
        // cursor would move the hand): the script starts with the session.
        if (!path_.empty()) text_ = "sleep 0.5\n";
    }
    [[nodiscard]] bool on() const { return !path_.empty(); }
    void motion(glm::dvec2 px, bool shift, bool ctrl, double now_s) {
        // A twist and a lean do not commute: each kind is written out before the other comes.
        if ((ctrl && shift && ctrl_ != glm::dvec2{0.0}) || (ctrl && !shift && twist_ != glm::dvec2{0.0})) flush();
        if (plain_ == glm::dvec2{0.0} && shift_ == glm::dvec2{0.0} && ctrl_ == glm::dvec2{0.0} && twist_ == glm::dvec2{0.0}) {
            catch_up(now_s);
            gathering_from_s_ = now_s;
        }
        (ctrl && shift ? twist_ : ctrl ? ctrl_ : shift ? shift_ : plain_) += px;
        if (now_s - gathering_from_s_ >= 1.0) flush();
    }
    void event(const std::string& command, double now_s) {
        flush();
        catch_up(now_s);
        text_ += command + "\n";
    }
    void flush() {
        if (!on()) return;
        moves(plain_, "");
        moves(shift_, "shift");
        moves(twist_, "ctrl+shift");
        moves(ctrl_, "ctrl");
        plain_ = shift_ = ctrl_ = twist_ = glm::dvec2{0.0};
    }
    // Sleeps until the script's time is the simulation's (the motions themselves take time too).
    void catch_up(double now_s) {
        if (!on() || now_s <= script_s_) return;
        char line[64];
        std::snprintf(line, sizeof line, "sleep %.3f\n", now_s - script_s_);
        text_ += line;
        script_s_ = now_s;
    }
    Result<void> write(double now_s) {
        flush();
        catch_up(now_s);
        return assets::write_text_file(path_, text_);
    }

private:
    void moves(glm::dvec2 px, const char* modifier) {
        if (px == glm::dvec2{0.0}) return;
        // The window reads keys and cursor once a frame (a few frames a second on lavapipe under Xvfb):
        // a modifier is held a quarter second either side of its motion.
        if (*modifier) add(std::string("keydown ") + modifier + "\nsleep 0.25\n", 0.25);
        // At most 4 pixels a piece: the X server doubles a relative motion beyond its threshold (4 by
        // default), and a replay through XTest would overshoot.
        const int pieces = std::max(1, static_cast<int>(std::ceil(std::max(std::abs(px.x), std::abs(px.y)) / 4.0)));
        int done_x = 0, done_y = 0;
        for (int i = 1; i <= pieces; ++i) {
            const int x = static_cast<int>(std::lround(px.x * i / pieces)) - done_x, y = static_cast<int>(std::lround(px.y * i / pieces)) - done_y;
            done_x += x;
            done_y += y;
            add("mousemove_relative -- " + std::to_string(x) + " " + std::to_string(y) + "\nsleep 0.004\n", 0.004);
        }
        if (*modifier) add("sleep 0.25\nkeyup " + std::string(modifier) + "\nsleep 0.25\n", 0.5);
    }
    void add(const std::string& text, double seconds) {
        text_ += text;
        script_s_ += seconds;
    }
    std::string path_, text_;
    glm::dvec2 plain_{0.0}, shift_{0.0}, ctrl_{0.0}, twist_{0.0};
    double gathering_from_s_ = 0.0, script_s_ = 0.0;
};

// The mouse: whole pixels and wheel clicks, one motion per reading (plain, with Shift for depth, with
// Ctrl to tilt), and the lesson's keys.
class MouseHand final : public TeacherHand {
public:
    MouseHand(World& world, sched::DeterministicClock& clock, devices::MouseKeyboardHands& mouse, ScriptedPointer& pointer, LessonControls& controls,
              XdoScript& script, PointerView view)
        : w_(world), clock_(clock), mouse_(mouse), pointer_(pointer), controls_(controls), script_(script), config_(lesson_mouse_config()), view_(view) {}
    glm::dvec3 position() const override { return mouse_.sample(mouse_.active_hand(), clock_.now_us()).position; }
    glm::dvec3 angles() const override { return mouse_.sample(mouse_.active_hand(), clock_.now_us()).rotation; }
    // Tab, as the window reads it; the cursor goes onto the hand switched to.
    bool two_hands() const override { return true; }
    bool turns_freely() const override { return false; }
    bool use(std::uint8_t hand) override {
        if (mouse_.active_hand() == (hand & 1u)) return true;
        script_.event("key Tab", now_s());
        pointer_.state.switch_hand = true;
        aim();
        clock_.run_for_us(40'000);
        after_wait();
        pointer_.state.switch_hand = false;
        aim();
        clock_.run_for_us(40'000);
        after_wait();
        return mouse_.active_hand() == (hand & 1u);
    }
    // The window's first frames: the cursor goes onto the hand.
    void start() {
        aim();
        clock_.run_for_us(1000);
    }
    void go(glm::dvec3 position_m) override {
        auto& s = pointer_.state;
        // The cursor's pixels for a metre of the hand where it is, as the window aims it.
        const int eye = eye_spot(view_.layout(s.window_px), s.cursor_px).eye;
        const glm::dvec2 px_per_m = px_per_m_at(view_, s.window_px, eye, position()).value_or(
            glm::dvec2{s.window_px.x / config_.workspace_width_m, s.window_px.y / config_.workspace_height_m});
        const glm::dvec3 d = position_m - position();
        motion({std::round(d.x * px_per_m.x), std::round(-d.z * px_per_m.y)}, false, false);
        const glm::dvec3 d2 = position_m - position();
        motion({0.0, std::round(-d2.y * px_per_m.y)}, true, false);
    }
    // Holding nothing: Ctrl+drag sideways, then up or down, then the wheel, each a turn about one
    // axis, so however the window splits them into readings they add up to the turn asked for.
    // Holding a stem: Ctrl+Shift+drag to twist it about its own axis, then one Ctrl+drag that takes
    // its tip where the turn puts it, as the window leans a held stem (lean_turn).
    void turn(glm::dvec3 angles_rad) override {
        aim();
        const auto& s = pointer_.state;
        const auto g = devices::MouseKeyboardHands::tilt_gesture(config_, angles(), angles_rad,
                                                                 s.lean_along ? std::optional<glm::dvec3>(s.lean_along_dir) : std::nullopt);
        if (g.held) {
            if (g.twist_px != 0) motion({static_cast<double>(g.twist_px), 0.0}, true, true);
            motion({static_cast<double>(g.right_px), static_cast<double>(g.down_px)}, false, true);
            return;
        }
        motion({static_cast<double>(g.right_px), 0.0}, false, true);
        motion({0.0, static_cast<double>(g.down_px)}, false, true);
        wheel(g.clicks);
    }
    void wheel(int clicks) {
        if (clicks == 0) return;
        auto& s = pointer_.state;
        for (int c = 0; c < std::abs(clicks); ++c) script_.event("keydown ctrl\nsleep 0.08\nclick " + std::string(clicks > 0 ? "4" : "5") + "\nsleep 0.08\nkeyup ctrl\nsleep 0.08", now_s());
        s.scroll += clicks;
        s.tilt_modifier = true;
        aim();
        clock_.run_for_us(1000);
        s.tilt_modifier = false;
        aim();
        clock_.run_for_us(1000);
    }
    void grab(bool down) override {
        pointer_.state.grab_button = down;
        script_.event(down ? "mousedown 1" : "mouseup 1", now_s());
    }
    // C, as the window reads it: LessonControls cuts the held stem for the role it is heading for.
    void cut(double) override { tap(cut_letter, "key c"); }
    // P, as the window reads it: LessonControls prunes at the active hand's cube.
    void prune() override { tap(prune_letter, "key p"); }
    void tap(char letter, const char* xdotool) {
        script_.event(xdotool, now_s());
        pointer_.state.set_letter(letter, true);
        clock_.run_for_us(40'000);
        after_wait();
        pointer_.state.set_letter(letter, false);
        clock_.run_for_us(40'000);
        after_wait();
    }
    void after_wait() {
        const auto& latest = w_.main.resource<const systems::ReceivedFrames>()->latest();
        last_ = controls_.update(pointer_.state, mouse_.active_hand(), latest, w_.trainee);
    }
    void press_enter() {
        script_.event("key Return", now_s());
        pointer_.state.finish_key = true;
        clock_.run_for_us(40'000);
        after_wait();
        score_ = last_.score;
        scored_at_us_ = clock_.now_us();
        pointer_.state.finish_key = false;
        clock_.run_for_us(40'000);
        after_wait();
    }
    const std::optional<Result<FormScore>>& score() const { return score_; }
    std::int64_t scored_at_us() const { return scored_at_us_; }

private:
    double now_s() const { return static_cast<double>(clock_.now_us()) * 1e-6; }
    // The window's reading of the pointer: aimed through its camera, the cursor put back on the hand
    // when it is to go there (the hands exactly where the mouse put them: device space is the world's
    // at the lesson's unturned camera).
    void aim() {
        std::array<std::optional<glm::dvec3>, 2> hands{mouse_.sample(0, clock_.now_us()).position, mouse_.sample(1, clock_.now_us()).position};
        aim_.aim(pointer_.state, view_, hands, [](glm::dvec2) {});
        tell_held_stem(pointer_.state, w_.main.resource<const systems::ReceivedFrames>()->latest(), mouse_.active_hand(), 0.0);
    }
    // One reading of the pointer with this motion and these keys held, then a tick to read it; a
    // modifier let go is read too (the window then puts the cursor back on the hand).
    void motion(glm::dvec2 px, bool shift, bool ctrl) {
        if (px == glm::dvec2{0.0} && !ctrl) return;
        script_.motion(px, shift, ctrl, now_s());
        auto& s = pointer_.state;
        s.depth_modifier = shift;
        s.tilt_modifier = ctrl;
        s.cursor_px += px;
        aim();
        clock_.run_for_us(1000);
        if (shift || ctrl) {
            s.depth_modifier = false;
            s.tilt_modifier = false;
            aim();
            clock_.run_for_us(1000);
        }
    }
    World& w_;
    sched::DeterministicClock& clock_;
    devices::MouseKeyboardHands& mouse_;
    ScriptedPointer& pointer_;
    LessonControls& controls_;
    XdoScript& script_;
    devices::MouseKeyboardHands::Config config_;
    PointerView view_;
    PointerAim aim_;
    LessonControls::Effects last_;
    std::optional<Result<FormScore>> score_;
    std::int64_t scored_at_us_ = 0;
};

// The simulation as the teacher sees it, on the deterministic clock.
class SimClassroom final : public Classroom {
public:
    SimClassroom(World& world, sched::DeterministicClock& clock, std::function<void()> after_wait)
        : w_(world), clock_(clock), after_wait_(std::move(after_wait)) {}
    double now_s() const override { return static_cast<double>(clock_.now_us()) * 1e-6; }
    void wait(double seconds) override {
        clock_.run_for_us(static_cast<std::int64_t>(seconds * 1e6));
        after_wait_();
    }
    std::size_t flower_count() const override { return w_.flowers.size(); }
    SeenFlower flower(std::size_t i) const override {
        const ecs::Entity e = w_.flowers[i].entity;
        SeenFlower f;
        f.species = w_.flowers[i].species;
        f.points_m = w_.sim.get<StemPoints>(e).position_m;
        if (const auto* twigs = w_.sim.try_get<const Twigs>(e)) {
            for (const ecs::Entity t : twigs->entities) {
                const auto* fork = w_.sim.try_get<const StemFork>(t);
                const auto* points = w_.sim.try_get<const StemPoints>(t);
                if (fork && points && fork->parent == e && points->position_m.size() >= 2) f.twig_aims_m.push_back(points->position_m[1]);
            }
        }
        const auto& rest = w_.sim.get<StemRestShape>(e);
        f.length_m = std::accumulate(rest.segment_length_m.begin(), rest.segment_length_m.end(), 0.0);
        if (const auto* children = w_.sim.try_get<const ecs::Children>(e)) {
            for (const ecs::Entity child : children->entities) {
                const auto* part = w_.sim.try_get<const Part>(child);
                if (!part || part->kind != PartKind::leaf || part->stem_point >= f.points_m.size()) continue;
                double along = 0.0;
                for (std::size_t k = 1; k <= part->stem_point; ++k) along += glm::length(f.points_m[k] - f.points_m[k - 1]);
                f.leaves.push_back({along, systems::part_middle(*part, w_.sim.get<StemPoints>(e), w_.sim.try_get<const StemFrame>(e))});
            }
        }
        if (const auto* twigs = w_.sim.try_get<const Twigs>(e)) {
            for (const ecs::Entity t : twigs->entities) {
                const auto* children = w_.sim.try_get<const ecs::Children>(t);
                const auto* points = w_.sim.try_get<const StemPoints>(t);
                if (!children || !points) continue;
                for (const ecs::Entity child : children->entities) {
                    const auto* part = w_.sim.try_get<const Part>(child);
                    if (!part || part->kind != PartKind::leaf || part->stem_point >= points->position_m.size()) continue;
                    f.leaves.push_back({0.0, systems::part_middle(*part, *points, w_.sim.try_get<const StemFrame>(t)), true});
                }
            }
        }
        f.diameter_m = rest.diameter_m;
        if (const auto* bending = w_.sim.try_get<const Bending>(e)) f.keeps_bend_beyond_rad = bending->permanent_set_rad;
        const auto& engagement = w_.sim.get<PinEngagement>(e);
        const auto& grip = w_.sim.get<KenzanGrip>(e);
        f.in_kenzan = engagement.in_kenzan;
        f.pins = static_cast<std::uint32_t>(engagement.pins.size());
        f.depth_m = engagement.depth_m;
        f.fallen = grip.fallen;
        f.fall_reason = grip.fall_reason;
        if (grip.yielded) {
            f.yield_holding_nm = grip.yield_holding_nm;
            f.yield_gravity_nm = grip.yield_gravity_nm;
        }
        return f;
    }
    std::optional<std::size_t> held(std::uint8_t hand) const override {
        const ecs::Entity e = w_.sim.get<HandGrip>(w_.hands[hand & 1u]).held;
        for (std::size_t i = 0; i < w_.flowers.size(); ++i) {
            if (w_.flowers[i].entity == e) return i;
        }
        return std::nullopt;
    }
    glm::dvec3 hand_at(std::uint8_t hand) const override { return w_.sim.get<HandProxy>(w_.hands[hand & 1u]).position_m; }
    glm::dvec3 kenzan_origin_m() const override { return w_.sim.single<Kenzan>()->origin_m; }
    double pin_height_m() const override { return w_.sim.single<Kenzan>()->pin_height_m(); }
    std::optional<double> water_z_m() const override {
        const auto* container = w_.sim.single<Container>();
        return container ? std::optional<double>(container->water_z_m) : std::nullopt;
    }

private:
    World& w_;
    sched::DeterministicClock& clock_;
    std::function<void()> after_wait_;
};

} // namespace

Result<DemoResult> run_lesson_demo(const LessonDef& lesson, const DemoOptions& options) {
    if (lesson.scoring != "form") return make_error(ErrorCode::invalid_argument, lesson.id + " copies its scene's sample; it has no form to demonstrate");
    auto scene = scene_for_lesson(lesson);
    if (!scene) return std::move(scene).error();
    const auto footprint = footprint_of(lesson);
    if (!footprint) return std::move(footprint).error();
    auto world = World::create(*scene);
    if (!world) return std::move(world).error();
    World& w = **world;
    sched::DeterministicClock clock(w.schedule);
    // The puppet devices (one a hand), or the mouse with the window's settings and keys.
    std::array<std::shared_ptr<PuppetDevice::Pose>, 2> poses;
    for (std::size_t h = 0; h < 2; ++h) {
        poses[h] = std::make_shared<PuppetDevice::Pose>();
        poses[h]->position_m = w.sim.get<HandProxy>(w.hands[h]).position_m;
    }
    PuppetHand puppet(poses, w);
    ScriptedPointer pointer;
    devices::MouseKeyboardHands mouse(pointer, lesson_mouse_config());
    LessonControls controls(lesson, *footprint);
    XdoScript script(options.xdotool_script);
    // The window's camera at its start, and its size (the window demonstration's).
    MouseHand mouse_hand(w, clock, mouse, pointer, controls, script, PointerView{rig_of(scene->display), render::StereoMode::side_by_side, 0.0});
    if (options.through_mouse) {
        for (const auto& h : scene->hands) mouse.place(h.hand, h.position_m);
        w.attach_device(0, mouse.hand(0));
        w.attach_device(1, mouse.hand(1));
        mouse_hand.start();
    } else {
        w.attach_device(0, std::make_unique<PuppetDevice>(poses[0]));
        w.attach_device(1, std::make_unique<PuppetDevice>(poses[1]));
    }
    TeacherHand& hand = options.through_mouse ? static_cast<TeacherHand&>(mouse_hand) : static_cast<TeacherHand&>(puppet);
    std::unique_ptr<SessionRecorder> recorder;
    if (!options.record_dir.empty()) {
        auto made = SessionRecorder::create(options.record_dir, /*real_time=*/false);
        if (!made) return std::move(made).error();
        recorder = std::move(made).value();
        recorder->attach(w);
    }
    SimClassroom room(w, clock, [&] {
        if (options.through_mouse) mouse_hand.after_wait();
    });
    DemoResult result;
    teach(lesson, model_arrangement(lesson, *footprint), room, hand, result, options);
    // What the simulation shows, measured as the app and `sim` see it (with the mouse: Enter, as the
    // window scores it).
    std::optional<Result<FormScore>> scored;
    std::int64_t scored_at_us = clock.now_us();
    if (options.through_mouse) {
        mouse_hand.press_enter();
        scored = mouse_hand.score();
        scored_at_us = mouse_hand.scored_at_us();
        if (script.on()) {
            if (auto written = script.write(room.now_s() + 2.0); !written) return std::move(written).error();
        }
        if (!scored) return make_error(ErrorCode::invalid_argument, "Enter gave no score");
    } else {
        const auto& frame = w.main.resource<const systems::ReceivedFrames>()->latest();
        scored = score_form(lesson, measure_arrangement(frame), *footprint, "demo");
    }
    if (!scored->ok()) return std::move(*scored).error();
    result.score = std::move(*scored).value();
    result.simulated_s = room.now_s();
    result.state_hash = w.state_hash();
    result.unused_access = w.schedule.unused_access();
    result.flowers = flower_outcomes(w.main.resource<const systems::ReceivedFrames>()->latest());
    if (recorder) {
        if (auto written = recorder->finish(lesson, "demonstration", scored_at_us, clock.now_us(), result.score.score, w); !written) {
            // Nothing half-made is left: the folder's files go (and the folder, if nothing else is in it).
            const auto folder = recorder->folder();
            recorder.reset();
            std::error_code ec;
            for (const char* name : {"left.csv", "right.csv", "commands.csv", "lesson.json"}) std::filesystem::remove(folder / name, ec);
            std::filesystem::remove(folder, ec);
            return std::move(written).error();
        }
    }
    return result;
}

} // namespace ikebana::game
