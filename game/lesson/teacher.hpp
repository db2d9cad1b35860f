#pragma once
// The teacher of the demonstration (lesson_demo.hpp), apart from what it works through: it sees the
// stems (a Classroom: the simulation itself, or the window's state read from outside), moves one hand
// (a TeacherHand: a puppet device, the mouse as the window reads it, or the real X pointer), and
// arranges the lesson's model form with them, one stem at a time.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "components/insertion.hpp"
#include "game/lesson/form_score.hpp"
#include "game/lesson/lesson_demo.hpp"

namespace ikebana::game {

// One flower as the teacher sees it.
struct SeenFlower {
    std::string species;
    std::vector<glm::dvec3> points_m; // bottom first
    double length_m = 0.0;
    double diameter_m = 0.0;
    bool in_kenzan = false;
    bool fallen = false;
    components::FallReason fall_reason = components::FallReason::none;
    double yield_holding_nm = 0.0, yield_gravity_nm = 0.0; // 0: the pins never gave way
    std::uint32_t pins = 0;
    double depth_m = 0.0;
};

// What the teacher sees, and time passing.
class Classroom {
public:
    virtual ~Classroom() = default;
    [[nodiscard]] virtual double now_s() const = 0;
    virtual void wait(double seconds) = 0;
    [[nodiscard]] virtual std::size_t flower_count() const = 0;
    [[nodiscard]] virtual SeenFlower flower(std::size_t i) const = 0;
    [[nodiscard]] virtual std::optional<std::size_t> held() const = 0; // by the teacher's hand (the right)
    [[nodiscard]] virtual glm::dvec3 kenzan_origin_m() const = 0;
    [[nodiscard]] virtual double pin_height_m() const = 0;
};

// The hand the teacher works through (device space, which the lessons map one to one onto the scene).
class TeacherHand {
public:
    virtual ~TeacherHand() = default;
    [[nodiscard]] virtual glm::dvec3 position() const = 0;
    [[nodiscard]] virtual glm::dvec3 angles() const = 0;
    virtual void go(glm::dvec3 position_m) = 0;
    virtual void turn(glm::dvec3 angles_rad) = 0;
    virtual void grab(bool down) = 0;
    virtual void cut(double keep_m) = 0;
    // How often a moving hand is set on its way (seconds): every tick of a puppet; a pointer that
    // must wait for the window to read each motion, less often.
    [[nodiscard]] virtual double step_s() const { return 0.01; }
    [[nodiscard]] virtual double step_m() const { return 1e9; }      // and at most this far at a time
    [[nodiscard]] virtual double turn_step_s() const { return 0.01; } // a turn likewise
    // Before a stem is taken: where the hand really is, if the hand can find out.
    virtual void look() {}
};

// Arranges the model form through the hand: for each stem, the shortest unused material of its
// species long enough, taken, cut, turned, pushed in at its place and let go. Steps go to `result`.
void teach(const LessonDef& lesson, const Arrangement& model, Classroom& room, TeacherHand& hand, DemoResult& result, const DemoOptions& options);

} // namespace ikebana::game
