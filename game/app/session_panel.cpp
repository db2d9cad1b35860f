#include "game/app/session_panel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include <imgui.h>

#include "game/lesson/role_colours.hpp"

namespace ikebana::game {

void show_score(SessionPanelModel& m, const FormScore& score, const LessonDef* lesson) {
    m.score = score.score;
    m.points = m.max_points = 0.0;
    for (const auto& c : score.criteria) m.points += c.points, m.max_points += c.max_points;
    for (const auto& r : score.rules) m.points += r.points, m.max_points += r.max_points;
    m.stems.clear();
    m.rules.clear();
    const auto plain = [](const std::string& tip) {
        const auto colon = tip.find(": ");
        return colon == std::string::npos ? tip : tip.substr(colon + 2);
    };
    for (const auto& c : score.criteria) {
        auto it = std::find_if(m.stems.begin(), m.stems.end(), [&](const auto& s) { return s.role == c.stem; });
        if (it == m.stems.end()) {
            std::size_t role = m.stems.size();
            if (lesson) {
                for (std::size_t i = 0; i < lesson->stems.size(); ++i) role = lesson->stems[i].role == c.stem ? i : role;
            }
            m.stems.push_back({c.stem, role_colour(role).rgb, {}});
            it = std::prev(m.stems.end());
        }
        const char* what = c.name == "length_mm" ? "length" : c.name == "tilt_deg" ? "tilt" : c.name == "azimuth_deg" ? "direction" : c.name == "region_mm" ? "place" : "match";
        char label[96];
        std::snprintf(label, sizeof label, "%s %.1f / %.0f", what, c.points, c.max_points);
        const bool full = c.points >= c.max_points - 1e-9;
        it->bars.push_back({label, c.max_points > 0.0 ? static_cast<float>(c.points / c.max_points) : 1.0f, full ? "" : plain(c.tip)});
    }
    // Each rule with its points beside the bars', so that what the panel shows adds up to the score
    // (the bars alone came to 89.6 of 90 under a score of 93 and the rules' points were never shown).
    for (const auto& r : score.rules) {
        char points[48];
        std::snprintf(points, sizeof points, " (%.1f / %.0f)", r.points, r.max_points);
        m.rules.push_back((r.ok ? "ok: " : "to do: ") + r.tip + points);
    }
}

double session_column_px(double area_width_px) { return std::clamp(0.3 * area_width_px, std::min(300.0, area_width_px / 3.0), 440.0); }

namespace {
constexpr double deg = 3.14159265358979323846 / 180.0;

// The held stem's lean seen from above (the viewer's side at the bottom): the distance from the middle
// is the tilt (the rim is lying flat), the angle its direction; the role's band in its colour, the stem
// a dot, red outside the band.
void draw_gauge(const HeldStemAdvice::Gauge& g, glm::vec3 colour) {
    const float size = std::min(140.0f, ImGui::GetContentRegionAvail().x);
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const ImVec2 c(at.x + 0.5f * size, at.y + 0.5f * size);
    const float rim = 0.5f * size - 4.0f;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    // Lesson convention: azimuth 0 toward the viewer (down here), + to the viewer's left.
    const auto spot = [&](double tilt, double azimuth) {
        const float r = rim * static_cast<float>(std::clamp(tilt / (90.0 * deg), 0.0, 1.0));
        return ImVec2(c.x - r * static_cast<float>(std::sin(azimuth)), c.y + r * static_cast<float>(std::cos(azimuth)));
    };
    draw->AddCircleFilled(c, rim, IM_COL32(250, 248, 242, 255), 48);
    draw->AddCircle(c, rim, IM_COL32(120, 120, 120, 255), 48);
    draw->AddCircle(c, 0.5f * rim, IM_COL32(200, 200, 200, 255), 32); // 45°
    const ImU32 band = ImGui::ColorConvertFloat4ToU32(ImVec4(colour.r, colour.g, colour.b, 0.45f));
    const double lo = std::max(0.0, g.target_tilt_rad - g.tilt_tolerance_rad), hi = std::min(90.0 * deg, g.target_tilt_rad + g.tilt_tolerance_rad);
    const double a0 = g.target_azimuth_rad ? *g.target_azimuth_rad - g.azimuth_tolerance_rad : 0.0;
    const double a1 = g.target_azimuth_rad ? *g.target_azimuth_rad + g.azimuth_tolerance_rad : 360.0 * deg;
    constexpr int pieces = 24;
    for (int k = 0; k < pieces; ++k) {
        const double b0 = a0 + (a1 - a0) * k / pieces, b1 = a0 + (a1 - a0) * (k + 1) / pieces;
        draw->AddQuadFilled(spot(lo, b0), spot(hi, b0), spot(hi, b1), spot(lo, b1), band);
    }
    const bool tilt_ok = std::abs(g.tilt_rad - g.target_tilt_rad) <= g.tilt_tolerance_rad;
    const bool way_ok = !g.target_azimuth_rad || g.tilt_rad < 1.0 * deg ||
                        std::abs(std::remainder(g.azimuth_rad - *g.target_azimuth_rad, 360.0 * deg)) <= g.azimuth_tolerance_rad;
    draw->AddLine(c, spot(g.tilt_rad, g.azimuth_rad), IM_COL32(60, 60, 60, 255), 2.0f);
    draw->AddCircleFilled(spot(g.tilt_rad, g.azimuth_rad), 5.0f, tilt_ok && way_ok ? IM_COL32(30, 150, 50, 255) : IM_COL32(210, 30, 30, 255));
    draw->AddText(ImVec2(c.x - 18.0f, at.y + size - 2.0f), IM_COL32(90, 90, 90, 255), "you");
    ImGui::Dummy(ImVec2(size, size + 14.0f));
    ImGui::SameLine();
    ImGui::BeginGroup();
    ImGui::TextWrapped("Seen from above, you at the bottom: the dot is the stem's lean (the rim: lying flat), the coloured band the form's.");
    ImGui::Text("now %.0f° %s", g.tilt_rad / deg, g.tilt_rad < 1.0 * deg ? "upright" : ("toward the " + direction_words(g.azimuth_rad)).c_str());
    ImGui::EndGroup();
}
} // namespace

SessionPanelActions SessionPanel::draw(const SessionPanelModel& model, float left_px, float width_px) {
    buttons_.clear();
    panels_.clear();
    SessionPanelActions act;
    const ImGuiIO& io = ImGui::GetIO();
    // The whole column, top to bottom: a press anywhere in it is the panel's, never a grab.
    ImGui::SetNextWindowPos(ImVec2(left_px, 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(width_px, io.DisplaySize.y), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(1.0f);
    // The title, the next step and the buttons stay put; what is below them scrolls (a trainee scrolled
    // the Next line out of view).
    ImGui::Begin("session", nullptr, ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted(model.title.c_str());
    if (!model.trainee.empty()) ImGui::TextDisabled("%s", model.trainee.c_str());
    ImGui::Separator();
    // The one line a beginner reads first.
    // Three lines kept for it whatever it says, so the buttons under it stay where they are; a longer
    // one gets the lines it needs (cut at three, "...leaning toward the viewer, across" hid the rest
    // under the buttons).
    const std::string next = "Next: " + model.next_step;
    const float next_h = ImGui::CalcTextSize(next.c_str(), nullptr, false, ImGui::GetContentRegionAvail().x).y;
    ImGui::BeginChild("next", ImVec2(0.0f, std::max(3.0f * ImGui::GetTextLineHeightWithSpacing(), next_h + ImGui::GetStyle().ItemSpacing.y) + 2.0f), false,
                      ImGuiWindowFlags_NoScrollbar);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.7f, 0.3f, 0.0f, 1.0f)); // dark orange, read on the light panel
    ImGui::TextUnformatted(next.c_str());
    ImGui::PopStyleColor();
    ImGui::PopTextWrapPos();
    ImGui::EndChild();
    ImGui::Spacing();
    // Two a row, each half the column: whole labels at any width the column gets.
    const float half = 0.5f * (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x);
    act.finish = tracked_button(buttons_, "Score (Enter)", "finish", half);
    ImGui::SameLine();
    act.ghosts = tracked_button(buttons_, model.ghosts_on ? "Hide form (G)" : "Show form (G)", "ghosts", half);
    act.restart = tracked_button(buttons_, "Start over (R)", "restart", half);
    ImGui::SameLine();
    act.back = tracked_button(buttons_, "Lessons (Esc)", "back", half);
    ImGui::BeginChild("below", ImVec2(0.0f, 0.0f), false);
    ImGui::PushTextWrapPos(0.0f);
    {
        // The wheel over it scrolls it, even with the left button held down for a stem (Dear ImGui
        // hovers no window while a press that began outside it lasts, so its own wheel did nothing).
        const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
        const bool over = io.MousePos.x >= at.x && io.MousePos.x < at.x + size.x && io.MousePos.y >= at.y && io.MousePos.y < at.y + size.y;
        if (over && io.MouseWheel != 0.0f && !ImGui::IsWindowHovered())
            ImGui::SetScrollY(std::clamp(ImGui::GetScrollY() - io.MouseWheel * 3.0f * ImGui::GetTextLineHeightWithSpacing(), 0.0f, ImGui::GetScrollMaxY()));
        // A stem just taken: its lines and gauge come first, in view (the result, scrolled down, had
        // hidden them above).
        if (model.holding && !was_holding_) ImGui::SetScrollY(0.0f);
        was_holding_ = model.holding;
    }
    if (!model.held.empty()) {
        ImGui::Separator();
        for (const auto& line : model.held) ImGui::TextUnformatted(line.c_str());
    }
    if (model.gauge) draw_gauge(*model.gauge, model.role_colour);
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
    if (model.score) {
        ImGui::Separator();
        // One rounding everywhere: the history, the report and the bars say 92.6 where this once said 93.
        ImGui::Text("Score: %.1f / 100", *model.score);
        ImGui::SameLine();
        // What a teacher hands back: the arrangement beside the form's model, each bar and tip, the trend.
        act.report = tracked_button(buttons_, "Report (PNG, PDF)", "report");
        if (!model.report_note.empty()) ImGui::TextDisabled("%s", model.report_note.c_str());
        // How the bars and the rules below make the score.
        if (model.max_points > 0.0)
            ImGui::TextDisabled("%.1f of %.0f points (the bars and the rules below) = %.1f %%", model.points, model.max_points, *model.score);
        for (const auto& s : model.stems) {
            ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(s.colour.r, s.colour.g, s.colour.b, 1.0f));
            ImGui::TextUnformatted(s.role.c_str());
            ImGui::PopStyleColor();
            for (const auto& b : s.bars) {
                ImGui::ProgressBar(b.fraction, ImVec2(-1.0f, 0.0f), b.label.c_str());
                if (!b.tip.empty()) ImGui::TextUnformatted(b.tip.c_str());
            }
        }
        for (const auto& r : model.rules) {
            ImGui::Bullet();
            ImGui::TextWrapped("%s", r.c_str());
        }
    } else if (!model.result.empty()) {
        ImGui::Separator();
        for (const auto& line : model.result) ImGui::TextUnformatted(line.c_str());
    }
    ImGui::Separator();
    if (ImGui::CollapsingHeader("Controls")) {
        for (const auto& line : model.controls) {
            // BulletText does not wrap: a bullet, then wrapped text beside it.
            ImGui::Bullet();
            ImGui::TextWrapped("%s", line.c_str());
        }
    }
    if (ImGui::CollapsingHeader("Details")) {
        for (const auto& line : model.details) ImGui::TextUnformatted(line.c_str());
    }
    ImGui::PopTextWrapPos();
    ImGui::EndChild();
    ImGui::PopTextWrapPos();
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    panels_.push_back({"session", {at.x, at.y}, {size.x, size.y}});
    ImGui::End();
    return act;
}

} // namespace ikebana::game
