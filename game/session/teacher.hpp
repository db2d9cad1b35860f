#pragma once
// The teacher of the demonstration (lesson_demo.hpp), apart from what it works through: it sees the
// stems (a Classroom: the simulation itself, or the window's state read from outside), moves the hands
// (a TeacherHand: puppet devices, the mouse as the window reads it, or the real X pointer; the right
// hand does most, the left joins it to bend a stem), and arranges the lesson's model form with them,
// one stem at a time.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "components/insertion.hpp"
#include "game/training/form_score.hpp"
#include "game/session/lesson_demo.hpp"

namespace ikebana::game {

// One flower as the teacher sees it.
struct SeenFlower {
    std::string species;
    std::vector<glm::dvec3> points_m; // bottom first
    std::vector<glm::dvec3> twig_aims_m; // on each twig growing from the stem, a segment out from its fork
    struct Leaf {
        double along_m;  // from the stem's bottom to where it grows (on a twig: to the twig's fork)
        glm::dvec3 at_m; // where it is (its middle)
        bool on_twig = false;
    };
    std::vector<Leaf> leaves; // on the stem, then on its twigs
    double length_m = 0.0;
    double diameter_m = 0.0;
    bool in_kenzan = false;
    bool fallen = false;
    components::FallReason fall_reason = components::FallReason::none;
    double yield_holding_nm = 0.0, yield_gravity_nm = 0.0; // 0: the pins never gave way
    std::uint32_t pins = 0;
    double depth_m = 0.0;
    double keeps_bend_beyond_rad = 0.0; // bent further than this, it stays bent (the species' permanent set)
};

// What the teacher sees, and time passing.
class Classroom {
public:
    virtual ~Classroom() = default;
    [[nodiscard]] virtual double now_s() const = 0;
    virtual void wait(double seconds) = 0;
    [[nodiscard]] virtual std::size_t flower_count() const = 0;
    [[nodiscard]] virtual SeenFlower flower(std::size_t i) const = 0;
    [[nodiscard]] virtual std::optional<std::size_t> held(std::uint8_t hand = 1) const = 0; // by the teacher's right (1) or left (0) hand
    [[nodiscard]] virtual glm::dvec3 hand_at(std::uint8_t hand) const = 0; // where a hand's cube is seen (1: the right)
    [[nodiscard]] virtual glm::dvec3 kenzan_origin_m() const = 0;
    [[nodiscard]] virtual double pin_height_m() const = 0;
    // The water's surface in the container (none: no container, or not seen).
    [[nodiscard]] virtual std::optional<double> water_z_m() const { return std::nullopt; }
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
    // Prunes where the hand is: the twig its cube touches off at its fork, or a leaf stripped (pruning_system).
    virtual void prune() = 0;
    // How often a moving hand is set on its way (seconds): every tick of a puppet; a pointer that
    // must wait for the window to read each motion, less often.
    [[nodiscard]] virtual double step_s() const { return 0.01; }
    [[nodiscard]] virtual double step_m() const { return 1e9; }      // and at most this far at a time
    [[nodiscard]] virtual double turn_step_s() const { return 0.01; } // a turn likewise
    // Before a stem is taken: where the hand really is, if the hand can find out.
    virtual void look() {}
    // From now on the moves, turns and presses go to this hand (0 the left, 1 the right); false if the
    // teacher has only the right. With a mouse this is Tab, and the button as it is goes with it to the
    // hand switched to: the hand switched away from keeps its grip.
    virtual bool use(std::uint8_t hand) { return hand == 1; }
    [[nodiscard]] virtual bool two_hands() const { return false; }
    // Can it turn a held stem about any axis, its own included, as a wrist does? The mouse's hand turns in
    // steps about the viewer's axes and the vertical. With a branch's curve on its side of the bark (tried), a
    // bend made lying on the table is turned round through the mouse as well (within 3 degrees), but tai's
    // line came out at 25 degrees, not the devices' 35, and the Shoka's stems parted 86 mm above the
    // water (the form: 60-80): through the mouse a stem is still bent held up.
    [[nodiscard]] virtual bool turns_freely() const { return true; }
};

// Arranges the model form through the hands: for each stem, the shortest unused material of its
// species long enough, taken, cut, bent if the form's line rises before it leans (and the hands are
// two), turned, pushed in at its place and let go. Steps go to `result`.
void teach(const LessonDef& lesson, const Arrangement& model, Classroom& room, TeacherHand& hand, DemoResult& result, const DemoOptions& options);

} // namespace ikebana::game
