#pragma once
// The lesson's column beside the scene (render::ScreenLayout keeps it free of the 3D view): what to do
// next in one short line, the buttons, the held stem against its role, the form's legend with G, the
// result after Enter, and on demand the full heads-up text and every control. Nothing of it is drawn
// over the scene, in any stereo mode (side by side, the column is drawn in each eye's half).
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "game/app/start_screen.hpp"
#include "game/lesson/lesson.hpp"
#include "game/training/form_score.hpp"
#include "game/world/lesson_scene.hpp"

namespace ikebana::game {

struct SessionPanelModel {
    std::string title;
    std::string trainee;
    std::string next_step;            // one line: what to do now
    std::vector<std::string> held;    // the held stem against the role it is heading for
    bool holding = false;             // the hand the mouse drives holds a stem (the tilt buttons show)
    std::optional<HeldStemAdvice::Gauge> gauge; // its lean against its role's band
    glm::vec3 role_colour{1.0f};
    bool ghosts_on = false;
    struct Legend {
        std::string role;
        glm::vec3 colour{1.0f};
        std::string target; // "630 mm above the kenzan, 15° toward the left front"
    };
    std::vector<Legend> legend;       // the form's roles, with G
    std::vector<std::string> result;  // after Enter, as the terminal has it (when there are no bars)
    // After Enter in a lesson: the score, and per stem a bar for each criterion with its tip.
    struct Bar {
        std::string label; // "tilt 8.0 / 10"
        float fraction = 0.0f;
        std::string tip;   // empty: within its band
    };
    struct StemResult {
        std::string role;
        glm::vec3 colour{1.0f};
        std::vector<Bar> bars;
    };
    std::optional<double> score;
    double points = 0.0, max_points = 0.0; // the bars' and the rules' points together, of which score is the share
    std::string report_note;          // where the last report went, or why it did not
    std::vector<StemResult> stems;
    std::vector<std::string> rules; // each form rule, met or with what to do
    std::vector<std::string> details; // the full heads-up text: time, flowers, hands
    std::vector<std::string> controls;
};

struct SessionPanelActions {
    bool finish = false, ghosts = false, restart = false, back = false;
    bool report = false; // after Enter: the session's report (PNG and PDF) for the trainee
    glm::dvec2 tilt_steps{0.0}; // the tilt buttons pressed: x right, y away (as Ctrl+arrows)
};

// A rectangle in the interface's pixels (one eye's area in side by side).
struct PanelRect {
    std::string name;
    glm::dvec2 min_px{0.0}, size_px{0.0};
};

class SessionPanel {
public:
    // Drawn in the column: x from `left_px`, the area's whole height.
    SessionPanelActions draw(const SessionPanelModel& model, float left_px, float width_px);
    [[nodiscard]] const std::vector<UiButton>& buttons() const { return buttons_; }
    // The windows drawn this frame (for --state-out's layout).
    [[nodiscard]] const std::vector<PanelRect>& panels() const { return panels_; }

private:
    bool was_holding_ = false;
    std::vector<UiButton> buttons_;
    std::vector<PanelRect> panels_;
};

// The score in the panel: per stem (in its role's colour) a bar for each criterion, with its tip where
// it lost points (without the tip's "role: ", which the bar's heading says), and each rule.
void show_score(SessionPanelModel& model, const FormScore& score, const LessonDef* lesson);

// The column's width for an area of this size: wide enough for the buttons and a line of advice, at
// most a third of the area.
[[nodiscard]] double session_column_px(double area_width_px);

} // namespace ikebana::game
