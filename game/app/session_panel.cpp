#include "game/app/session_panel.hpp"

#include <algorithm>

#include <imgui.h>

namespace ikebana::game {

double session_column_px(double area_width_px) { return std::clamp(0.3 * area_width_px, std::min(300.0, area_width_px / 3.0), 440.0); }

SessionPanelActions SessionPanel::draw(const SessionPanelModel& model, float left_px, float width_px) {
    buttons_.clear();
    panels_.clear();
    SessionPanelActions act;
    const ImGuiIO& io = ImGui::GetIO();
    // The whole column, top to bottom: a press anywhere in it is the panel's, never a grab.
    ImGui::SetNextWindowPos(ImVec2(left_px, 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(width_px, io.DisplaySize.y), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(1.0f);
    // A scroll bar when the result runs past the bottom.
    ImGui::Begin("session", nullptr, ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                                         ImGuiWindowFlags_NoSavedSettings);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted(model.title.c_str());
    if (!model.trainee.empty()) ImGui::TextDisabled("%s", model.trainee.c_str());
    ImGui::Separator();
    // The one line a beginner reads first.
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.7f, 0.3f, 0.0f, 1.0f)); // dark orange, read on the light panel
    ImGui::TextUnformatted(("Next: " + model.next_step).c_str());
    ImGui::PopStyleColor();
    ImGui::Spacing();
    // Two a row, each half the column: whole labels at any width the column gets.
    const float half = 0.5f * (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x);
    act.finish = tracked_button(buttons_, "Score (Enter)", "finish", half);
    ImGui::SameLine();
    act.ghosts = tracked_button(buttons_, model.ghosts_on ? "Hide form (G)" : "Show form (G)", "ghosts", half);
    act.restart = tracked_button(buttons_, "Start over (R)", "restart", half);
    ImGui::SameLine();
    act.back = tracked_button(buttons_, "Lessons (Esc)", "back", half);
    if (!model.held.empty()) {
        ImGui::Separator();
        for (const auto& line : model.held) ImGui::TextUnformatted(line.c_str());
    }
    if (model.holding) {
        // The mouse alone can tilt it too: a step a press, as Ctrl+arrows.
        ImGui::TextUnformatted("Lean it 5° (or Ctrl+arrows):");
        const float quarter = 0.25f * (ImGui::GetContentRegionAvail().x - 3.0f * ImGui::GetStyle().ItemSpacing.x);
        if (tracked_button(buttons_, "left", "tilt:left", quarter)) act.tilt_steps.x -= 1.0;
        ImGui::SameLine();
        if (tracked_button(buttons_, "right", "tilt:right", quarter)) act.tilt_steps.x += 1.0;
        ImGui::SameLine();
        if (tracked_button(buttons_, "away", "tilt:away", quarter)) act.tilt_steps.y += 1.0;
        ImGui::SameLine();
        if (tracked_button(buttons_, "near", "tilt:toward", quarter)) act.tilt_steps.y -= 1.0;
    }
    if (!model.legend.empty()) {
        ImGui::Separator();
        ImGui::TextUnformatted("The form (G): rods over the kenzan, the model behind the container");
        for (const auto& l : model.legend) {
            ImGui::ColorButton(("##" + l.role).c_str(), ImVec4(l.colour.r, l.colour.g, l.colour.b, 1.0f),
                               ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop, ImVec2(12.0f, 12.0f));
            ImGui::SameLine();
            ImGui::TextUnformatted((l.role + ": " + l.target).c_str());
        }
    }
    if (!model.result.empty()) {
        ImGui::Separator();
        for (const auto& line : model.result) ImGui::TextUnformatted(line.c_str());
    }
    ImGui::Separator();
    if (ImGui::CollapsingHeader("Controls")) {
        for (const auto& line : model.controls) ImGui::BulletText("%s", line.c_str());
    }
    if (ImGui::CollapsingHeader("Details")) {
        for (const auto& line : model.details) ImGui::TextUnformatted(line.c_str());
    }
    ImGui::PopTextWrapPos();
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    panels_.push_back({"session", {at.x, at.y}, {size.x, size.y}});
    ImGui::End();
    return act;
}

} // namespace ikebana::game
