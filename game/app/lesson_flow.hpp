#pragma once
// What the trainee window does with a frame's keys: a lesson's (C cuts for the role in hand, G shows
// the form's ghosts, R starts over, Enter scores against the form: LessonControls, the same object a
// scripted mouse drives), and Enter in free practice (scored against the scene's sample, if it has
// one). Results go to the terminal and the HUD (a lesson's long tips wrapped to an eye's half).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "components/presentation.hpp"
#include "components/snapshot.hpp"
#include "engine/platform/pointer_input.hpp"
#include "engine/render/draw_list.hpp"
#include "game/lesson/lesson.hpp"
#include "game/scene/scene.hpp"
#include "game/session/lesson_controls.hpp"
#include "game/species/species.hpp"
#include "game/training/form_score.hpp"
#include "systems/haptics/trainee_command_system.hpp"

namespace ikebana::game {

class LessonFlow {
public:
    // For one world: the lesson (null in free practice), the scene's sample, where the kenzan stands,
    // the scenery drawn without ghosts, and the species the ghosts' model flowers are drawn as.
    LessonFlow(const LessonDef* lesson, KenzanFootprint footprint, std::vector<SampleStem> sample, glm::dvec3 kenzan_at_m,
               render::DrawList sample_scenery, const std::map<std::string, SpeciesDef>& species);

    struct Outcome {
        std::optional<FormScore> scored; // a score to count and store (a lesson's, or free practice against a sample)
        bool restart = false;            // R: the lesson again from the start
    };
    Outcome update(const platform::PointerState& keys, std::uint8_t active_hand, const components::FrameSnapshot& latest,
                   systems::TraineeChannel& trainee, components::HudInfo& hud, components::Scenery& scenery);
    [[nodiscard]] bool ghosts() const noexcept { return controls_ && controls_->ghosts(); }
    // The lesson's keys and what they last said (null in free practice without a form).
    [[nodiscard]] const LessonControls* controls() const noexcept { return controls_ ? &*controls_ : nullptr; }
    // The last result, as the terminal shows it (the HUD's copy is wrapped and spelt in ASCII).
    [[nodiscard]] const std::vector<std::string>& result() const noexcept { return result_; }
    // The last score with its criteria (none yet, or a scene's free practice without a lesson).
    [[nodiscard]] const std::optional<FormScore>& last_score() const noexcept { return last_score_; }

private:
    void show_result(const std::vector<std::string>& lines, components::HudInfo& hud);

    const LessonDef* lesson_;
    KenzanFootprint footprint_;
    std::vector<SampleStem> sample_;
    glm::dvec3 kenzan_at_m_;
    render::DrawList sample_scenery_;
    const std::map<std::string, SpeciesDef>& species_;
    std::optional<LessonControls> controls_;
    bool enter_was_down_ = false;
    std::vector<std::string> result_;
    std::optional<FormScore> last_score_;
};

} // namespace ikebana::game
