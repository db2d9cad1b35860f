#pragma once
// What the trainee window shows before a lesson and around one, drawn with Dear ImGui (one eye's
// layout; render::UiLayer puts it in both): the start screen (the trainee's name, the lessons with
// their form's diagram and numbers, the hands, the controls, the last results and their trend) and,
// during a lesson, a small panel with the active hand, what it holds, the target of the role it is
// heading for, and buttons for what the keys do.
#include <array>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "game/lesson/lesson.hpp"
#include "game/progress/progress_db.hpp"

namespace ikebana::game {

// A button where a script (or a test) can find it: its label and its rectangle in window pixels, in
// the left eye's copy.
struct UiButton {
    std::string label;
    glm::dvec2 min_px{0.0}, max_px{0.0};
};

// An interface button that remembers where it was drawn (window pixels, the left eye's copy in side by
// side), for scripts that work the window: inside a UI frame.
bool tracked_button(std::vector<UiButton>& buttons, const std::string& label, const std::string& name, float width = 0.0f, float height = 0.0f);

// Items side by side while they fit `width` (from where the first is drawn), then on the next row:
// call place(label) before each; inside a UI frame.
class ButtonRow {
public:
    explicit ButtonRow(float width);
    // Before a button (or radio button, or text) with this label: on this row if it fits, else the next.
    void place(const char* label, float extra_px = 0.0f);

private:
    float right_;
    bool any_ = false;
};

// A lesson's scores as the start screen draws them (pure, for tests): each session a point, x across
// [0, width], y from 0 (the axis' floor) to 1 (100); which points carry their score and day (as many
// as fit, at least `label_px` apart, the last always); the floor: 100 down to the ten below the lowest
// score, at most to 0, at least to 50, so that scores between 70 and 100 do not lie flat along the top.
struct TrendPoint {
    float x = 0.0f, y = 0.0f;
    bool labelled = false;
    bool demonstration = false; // drawn hollow
    std::string score;          // "87"
    std::string day;            // "11-25"
};
struct TrendLayout {
    double floor_score = 50.0;
    std::vector<TrendPoint> points;
};
[[nodiscard]] TrendLayout trend_layout(const std::vector<const SessionRecord*>& sessions, float width, float label_px);

struct StartScreenModel {
    std::vector<LessonDef> lessons;
    std::array<std::string, 2> hands;  // what each hand is: a device's name, or the mouse
    std::string trainee;               // edited on the screen
    std::vector<SessionRecord> recent; // this trainee's sessions, oldest first
    std::string progress_note;         // where results are kept, or why they are not
    // How the scene is shown ("mono", "sbs", "anaglyph", "rows"), chosen here unless --stereo fixed it.
    std::string display = "mono";
    bool display_fixed = false;
};

struct StartChoice {
    enum class Kind { none, lesson, quit, replay } kind = Kind::none;
    std::string lesson;    // its id
    std::string recording; // replay: the past session's recording
};

class StartScreen {
public:
    // Inside a UI frame. The name typed is written back to the model.
    StartChoice draw(StartScreenModel& model);
    [[nodiscard]] const std::vector<UiButton>& buttons() const { return buttons_; }

private:
    std::size_t selected_ = 0;
    bool name_loaded_ = false;
    bool defaulted_ = false;
    std::array<char, 64> name_{};
    std::vector<UiButton> buttons_;
};

} // namespace ikebana::game
