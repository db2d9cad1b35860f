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
