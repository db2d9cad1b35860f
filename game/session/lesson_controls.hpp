#pragma once
// A lesson's keys, one object for the window and for a scripted mouse: C cuts the held stem to what
// its role wants (through the trainee channel, the cutting system does the cut), G shows or hides the
// form's targets, R asks to start over, Enter scores the form. Each reading of the pointer also gives
// the lines the HUD shows about the lesson and the stem in the hand. Keys act when pressed, not while
// held.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "components/snapshot.hpp"
#include "engine/devices/mouse_keyboard_device.hpp"
#include "engine/platform/pointer_input.hpp"
#include "game/training/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "game/world/lesson_scene.hpp"

namespace ikebana::systems {
class TraineeChannel;
}

namespace ikebana::game {

// What P would take at the free hand's cube, as the pruning system chooses it (the twig nearest the cube
// cut at its fork, or the leaf or blossom nearest it, within the cube's half edge): "P here: strips a
// leaf of the chrysanthemum", or nothing when nothing is in reach. (A hand that holds a stem prunes too:
// a twig or leaf of the stem it holds, near its fist.)
[[nodiscard]] std::string prune_preview(const components::FrameSnapshot& frame, std::uint8_t hand);


// The HUD's font is ASCII: degrees, plus-minus and times are spelt out there (a terminal keeps them).
[[nodiscard]] std::string ascii_for_hud(std::string text);
// Words into lines of at most `width` characters (a longer word stands alone; later lines indented).
[[nodiscard]] std::vector<std::string> wrap_words(const std::string& text, std::size_t width);
// A species' id as a trainee reads it ("willow_branch": "willow branch").
[[nodiscard]] std::string species_words(std::string id);
// Both, at the width of one eye's half in side by side.
[[nodiscard]] std::vector<std::string> hud_lines_of(const std::string& text);

// The mouse on a lesson's table: the window's width spans 0.7 m, its height 0.6 m; the hands reach
// the materials in front of the container and the tallest stem's height above it.
[[nodiscard]] devices::MouseKeyboardHands::Config lesson_mouse_config();

// A lesson's keys (the engine reads letters; what they do is the lesson's).
inline constexpr char cut_letter = 'C';   // cut the held stem to the length its role wants
inline constexpr char prune_letter = 'P'; // prune at the cube: the twig nearest it off at its fork, or a leaf stripped
inline constexpr char ghost_letter = 'G'; // show or hide the form's targets and its model
inline constexpr char reset_letter = 'R'; // start the lesson again

class LessonControls {
public:
    LessonControls(const LessonDef& lesson, KenzanFootprint footprint) : lesson_(lesson), footprint_(footprint) {}

    struct Effects {
        std::string cut_for;               // the role a cut was made for (empty: none this reading)
        double cut_to_m = 0.0;
        bool ghosts_toggled = false;
        bool restart = false;
        std::optional<Result<FormScore>> score; // Enter, in a form lesson
    };
    // One reading of the pointer and keys, with the latest frame and the hand the mouse drives.
    Effects update(const platform::PointerState& in, std::uint8_t hand, const components::FrameSnapshot& latest, systems::TraineeChannel& trainee);

    [[nodiscard]] bool ghosts() const noexcept { return ghosts_; }
    // What the HUD says about the lesson now (ASCII, wrapped for half a window).
    [[nodiscard]] const std::vector<std::string>& hud_lines() const noexcept { return lines_; }
    // For the window's panel: what to do now, in one short line; the held stem against the role it is
    // heading for (as the HUD says it, unwrapped).
    [[nodiscard]] const std::string& next_step() const noexcept { return next_step_; }
    [[nodiscard]] const std::vector<std::string>& advice() const noexcept { return advice_; }
    [[nodiscard]] const std::optional<HeldStemAdvice::Gauge>& gauge() const noexcept { return gauge_; }
    // Where up from its end a press of this hand should take the stem in reach (grip_along_m).
    [[nodiscard]] double grip_along_m(const components::FrameSnapshot& latest, std::uint8_t hand) const {
        return game::grip_along_m(lesson_, footprint_, latest, hand);
    }

private:
    const LessonDef& lesson_;
    KenzanFootprint footprint_;
    bool ghosts_ = false;
    bool prune_was_down_ = false;
    // After P: how many pieces lay loose before it, and for how many more readings the outcome is said
    // (what came off, or that nothing was under the cube).
    std::size_t cuttings_before_prune_ = 0;
    int prune_said_for_ = 0;
    bool pruned_ = false;
    bool cut_was_down_ = false, ghost_was_down_ = false, reset_was_down_ = false, enter_was_down_ = false;
    std::vector<std::string> lines_;
    std::string next_step_;
    bool scored_ = false; // Enter was pressed and no stem has been taken since
    // Follows the held stem, and one just let go in the pins (held_, let_go_, sank_).
    void watch_sinking(const components::FrameSnapshot& latest, const components::HandStatus& hand, const std::string& role);
    // What a press of this hand would do now, in words.
    [[nodiscard]] std::string reach_words(const components::FrameSnapshot& latest, std::uint8_t hand) const;
    std::vector<std::string> advice_;
    std::optional<HeldStemAdvice::Gauge> gauge_;
    // The stem the hand last held, and how it leaned then: let go in the pins, it is watched for a few
    // seconds, and if it sinks well past that the next step says so (a trainee's shin, let go at 15°
    // in its band, was scored at 30° with no word).
    struct Watched {
        std::int32_t flower = -1;
        std::string role;
        double tilt_rad = 0.0;
        int readings_left = 0;
    };
    Watched held_, let_go_;
    int cut_refused_for_ = 0; // readings left to say why C cut nothing (the hand held what it would cut off)
    std::string sank_;
};

// Each role's target as the form gives it, for the legend beside the G rods: "630 mm above the kenzan,
// 15° ±5° toward the left front, in the back left".
[[nodiscard]] std::string role_target_words(const LessonDef& lesson, std::size_t role);

} // namespace ikebana::game
