#include "game/app/lesson_flow.hpp"

#include <cstdio>

#include "game/training/arrangement_score.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/world/sample_arrangement.hpp"

namespace ikebana::game {

LessonFlow::LessonFlow(const LessonDef* lesson, KenzanFootprint footprint, std::vector<SampleStem> sample, glm::dvec3 kenzan_at_m,
                       render::DrawList sample_scenery, const std::map<std::string, SpeciesDef>& species)
    : lesson_(lesson), footprint_(footprint), sample_(std::move(sample)), kenzan_at_m_(kenzan_at_m), sample_scenery_(std::move(sample_scenery)),
      species_(species) {
    if (lesson_) controls_.emplace(*lesson_, footprint_);
}

LessonFlow::Outcome LessonFlow::update(const platform::PointerState& keys, std::uint8_t active_hand, const components::FrameSnapshot& latest,
                                       systems::TraineeChannel& trainee, components::HudInfo& hud, components::Scenery& scenery) {
    Outcome out;
    if (controls_) {
        // A form lesson's Enter is scored here.
        const auto effects = controls_->update(keys, active_hand, latest, trainee);
        hud.lesson = controls_->hud_lines();
        if (!effects.cut_for.empty()) std::printf("ikebana: cut for %s to %.0f mm\n", effects.cut_for.c_str(), effects.cut_to_m * 1e3);
        if (effects.ghosts_toggled) {
            scenery.list = sample_scenery_;
            scenery.labels.clear();
            if (controls_->ghosts()) {
                add_form_ghosts(scenery.list, *lesson_, footprint_, kenzan_at_m_, &latest);
                add_model_flowers(scenery.list, *lesson_, footprint_, model_plate_origin(*lesson_, kenzan_at_m_), species_);
                scenery.labels = form_labels(*lesson_, footprint_, kenzan_at_m_, model_plate_origin(*lesson_, kenzan_at_m_), &latest);
            }
        }
        if (effects.score) show_result(effects.score->ok() ? (*effects.score)->lines() : std::vector<std::string>{"RESULT: " + effects.score->error().message}, hud);
        if (effects.score && effects.score->ok()) out.scored = **effects.score;
        if (out.scored) last_score_ = out.scored;
        out.restart = effects.restart;
    }
    const bool form = lesson_ && lesson_->scoring == "form";
    if (!form && keys.finish_key && !enter_was_down_) {
        if (lesson_ && !sample_.empty()) {
            // The free-practice lesson: scored as `lesson score` scores it, and stored like a form's.
            FormScore result = score_sample(*lesson_, measure_arrangement(latest), sample_);
            show_result(result.lines(), hud);
            last_score_ = result;
            out.scored = std::move(result);
        } else {
            const auto result = score_arrangement(arranged_stems(latest), sample_, kenzan_at_m_);
            show_result(sample_.empty() ? std::vector<std::string>{"RESULT: free practice (this scene has no sample)"} : result.lines(), hud);
        }
    }
    enter_was_down_ = keys.finish_key;
    return out;
}

void LessonFlow::show_result(const std::vector<std::string>& lines, components::HudInfo& hud) {
    result_ = lines;
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

} // namespace ikebana::game
