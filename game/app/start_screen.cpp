#include "game/app/start_screen.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include <imgui.h>

#include "game/lesson/form_table.hpp"
#include "game/lesson/role_colours.hpp"

namespace ikebana::game {
namespace {


// The role's colour (game/lesson/role_colours.hpp), as the HUD, the rods and the history draw it.
ImU32 role_colour_u32(std::size_t role) {
    const glm::vec3 c = role_colour(role).rgb;
    return ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, 1.0f));
}


// The form seen from the front and from above: each main stem at its nominal length, tilt and
// direction from the kenzan, over the container.
void form_diagram(const LessonDef& l, float width) {
    const float height = 130.0f;
    const float half = 0.5f * width - 6.0f;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    double longest = 0.05;
    for (std::size_t i = 0; i < l.stems.size(); ++i) longest = std::max(longest, nominal_length_m(l, i));
    const double reach = std::max(longest, 0.5 * l.container.width_m);
    // Front view: the container's side at the bottom, stems up from the kenzan.
    const float front_scale = static_cast<float>((height - 30.0) / reach);
    const ImVec2 base(at.x + 0.5f * half + static_cast<float>(l.kenzan_offset_m.x) * front_scale, at.y + height - 22.0f);
    draw->AddRectFilled(ImVec2(at.x, at.y), ImVec2(at.x + half, at.y + height), IM_COL32(246, 243, 236, 255));
    const float cw = static_cast<float>(l.container.width_m) * front_scale;
    const float ch = std::max(6.0f, static_cast<float>(l.container.depth_m) * front_scale);
    draw->AddRectFilled(ImVec2(at.x + 0.5f * half - 0.5f * cw, base.y - 2.0f), ImVec2(at.x + 0.5f * half + 0.5f * cw, base.y - 2.0f + ch),
                        IM_COL32(120, 110, 100, 255), 3.0f);
    // From above: the container's rim, stems out from the kenzan (the viewer is at the bottom).
    const ImVec2 top_at(at.x + half + 12.0f, at.y);
    const float top_scale = static_cast<float>((0.5 * height - 8.0) / reach);
    const ImVec2 centre(top_at.x + 0.5f * half, top_at.y + 0.5f * height);
    draw->AddRectFilled(top_at, ImVec2(top_at.x + half, top_at.y + height), IM_COL32(246, 243, 236, 255));
    if (l.container.shape == ContainerShape::rectangular) {
        const float w = 0.5f * static_cast<float>(l.container.width_m) * top_scale, d = 0.5f * static_cast<float>(l.container.front_to_back_m) * top_scale;
        draw->AddRect(ImVec2(centre.x - w, centre.y - d), ImVec2(centre.x + w, centre.y + d), IM_COL32(120, 110, 100, 255), 2.0f, 0, 2.0f);
    } else {
        draw->AddCircle(centre, 0.5f * static_cast<float>(l.container.width_m) * top_scale, IM_COL32(120, 110, 100, 255), 48, 2.0f);
    }
    const ImVec2 kenzan_top(centre.x + static_cast<float>(l.kenzan_offset_m.x) * top_scale, centre.y - static_cast<float>(l.kenzan_offset_m.y) * top_scale);
    for (std::size_t i = l.stems.size(); i-- > 0;) {
        const auto& m = l.stems[i];
        const double length = nominal_length_m(l, i);
        const double tilt = m.tilt_rad.target;
        const double az = m.azimuth_rad ? m.azimuth_rad->target : 0.0;
        // Azimuth 0 toward the viewer, + to the viewer's left: seen from the front, left is -x.
        const float side = static_cast<float>(-std::sin(az) * std::sin(tilt) * length);
        const float up = static_cast<float>(std::cos(tilt) * length);
        const float toward = static_cast<float>(std::cos(az) * std::sin(tilt) * length);
        draw->AddLine(base, ImVec2(base.x + side * front_scale, base.y - up * front_scale), role_colour_u32(i), 3.0f);
        draw->AddCircleFilled(ImVec2(base.x + side * front_scale, base.y - up * front_scale), 4.0f, role_colour_u32(i));
        draw->AddLine(kenzan_top, ImVec2(kenzan_top.x + side * top_scale, kenzan_top.y + toward * top_scale), role_colour_u32(i), 3.0f);
        draw->AddCircleFilled(ImVec2(kenzan_top.x + side * top_scale, kenzan_top.y + toward * top_scale), 4.0f, role_colour_u32(i));
    }
    draw->AddText(ImVec2(at.x + 4.0f, at.y + 2.0f), IM_COL32(90, 90, 90, 255), "front");
    draw->AddText(ImVec2(top_at.x + 4.0f, top_at.y + 2.0f), IM_COL32(90, 90, 90, 255), "from above (you: below)");
    ImGui::Dummy(ImVec2(width, height + 4.0f));
}

void form_numbers(const LessonDef& l) {
    if (l.stems.empty()) {
        ImGui::TextWrapped("Free practice: copy the sample arrangement; the score compares each stem with the sample's.");
        return;
    }
    if (ImGui::BeginTable("numbers", 4, ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg)) {
        ImGui::TableSetupColumn("stem");
        ImGui::TableSetupColumn("length");
        ImGui::TableSetupColumn("tilt");
        ImGui::TableSetupColumn("leaning toward");
        ImGui::TableHeadersRow();
        for (const FormTableRow& row : form_table(l)) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            if (row.role >= 0) ImGui::PushStyleColor(ImGuiCol_Text, role_colour_u32(static_cast<std::size_t>(row.role)));
            ImGui::TextUnformatted(row.stem.c_str());
            if (row.role >= 0) ImGui::PopStyleColor();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(row.length.c_str());
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(row.tilt.c_str());
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(row.leaning.c_str());
        }
        ImGui::EndTable();
    }
    const char* shape = l.container.shape == ContainerShape::vase ? "vase" : l.container.shape == ContainerShape::rectangular ? "rectangular suiban" : "round suiban";
    ImGui::TextDisabled("%s %.0f mm wide, %.0f mm deep", shape, l.container.width_m * 1e3, l.container.depth_m * 1e3);
    std::string materials;
    for (const auto& m : l.materials) materials += (materials.empty() ? "" : ", ") + (m.count > 1 ? std::to_string(m.count) + " " : "") + m.species;
    ImGui::TextDisabled("on the table: %s", materials.c_str());
}

// The recording a past session can be replayed from (its session.json is written when it ends).
bool replayable(const SessionRecord& s) {
    std::error_code ec;
    return !s.recording.empty() && std::filesystem::is_regular_file(std::filesystem::path(s.recording) / "session.json", ec);
}

// A lesson's scores over its sessions, oldest left: each a point (a demonstration's hollow) labelled
// with its score above and its day below, as many labels as fit (the last always), the 50 and 100
// lines behind, the full date, kind and score when the pointer is over a point. The last
// `most_shown` sessions (the caption says how many there are).
constexpr std::size_t most_shown = 20;
void trend(const std::vector<const SessionRecord*>& sessions, float width) {
    const float plot_h = 64.0f, label_h = ImGui::GetTextLineHeight();
    const float height = label_h + plot_h + label_h + 6.0f;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    ImGui::Dummy(ImVec2(width, height));
    const float axis = at.x + 30.0f, left = axis + 14.0f, right = at.x + width - 16.0f;
    const float top = at.y + label_h + 2.0f, bottom = top + plot_h;
    const TrendLayout layout = trend_layout(sessions, right - left, 46.0f);
    const auto floor_score = static_cast<float>(layout.floor_score);
    const ImU32 guide = IM_COL32(150, 150, 150, 90), text = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    for (const float level : {floor_score, 0.5f * (floor_score + 100.0f), 100.0f}) {
        const float y = bottom - plot_h * (level - floor_score) / (100.0f - floor_score);
        draw->AddLine(ImVec2(axis, y), ImVec2(right, y), guide);
        char tick[8];
        std::snprintf(tick, sizeof tick, "%.0f", static_cast<double>(level));
        draw->AddText(ImVec2(axis - 4.0f - ImGui::CalcTextSize(tick).x, y - 0.5f * label_h), text, tick);
    }
    const auto at_point = [&](const TrendPoint& p) { return ImVec2(left + p.x, bottom - plot_h * p.y); };
    const ImU32 ink = ImGui::GetColorU32(ImGuiCol_PlotLines);
    for (std::size_t i = 1; i < layout.points.size(); ++i) draw->AddLine(at_point(layout.points[i - 1]), at_point(layout.points[i]), ink, 1.5f);
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const SessionRecord* hovered = nullptr;
    for (std::size_t k = 0; k < layout.points.size(); ++k) {
        const TrendPoint& tp = layout.points[k];
        const ImVec2 p = at_point(tp);
        if (tp.demonstration) draw->AddCircle(p, 4.0f, ink, 12, 1.5f);
        else draw->AddCircleFilled(p, 4.0f, ink);
        if (std::abs(mouse.x - p.x) < 6.0f && std::abs(mouse.y - p.y) < 6.0f) hovered = sessions[k];
        if (!tp.labelled) continue;
        const float sw = ImGui::CalcTextSize(tp.score.c_str()).x;
        draw->AddText(ImVec2(p.x - 0.5f * sw, p.y - label_h - 2.0f), ImGui::GetColorU32(ImGuiCol_Text), tp.score.c_str());
        const float dw = ImGui::CalcTextSize(tp.day.c_str()).x;
        draw->AddText(ImVec2(std::max(axis, std::min(p.x - 0.5f * dw, right + 16.0f - dw)), bottom + 3.0f), text, tp.day.c_str());
    }
    if (hovered) {
        ImGui::BeginTooltip();
        ImGui::Text("%s UTC: %.1f / 100 (%s)", iso_utc(hovered->started_unix_s).substr(0, 16).c_str(), hovered->result.score, hovered->kind.c_str());
        ImGui::EndTooltip();
    }
}

// The lesson's name as the lessons list gives it ("Sogetsu: Basic Upright Style"), else its id.
std::string lesson_name(const StartScreenModel& model, const std::string& id) {
    for (const auto& l : model.lessons) {
        if (l.id == id) return l.school + ": " + l.title;
    }
    return id;
}

// Returns the recording to replay when its button is pressed.
std::optional<std::string> last_results(const StartScreenModel& model, std::vector<UiButton>& items) {
    std::optional<std::string> replay;
    if (model.recent.empty()) {
        ImGui::TextDisabled("No results yet: a lesson's Enter scores it and keeps the score here.");
        return replay;
    }
    // Each lesson's sessions in order: a caption with the last and the best, the last recorded one to
    // watch again, and the trend.
    std::vector<std::string> order;
    std::map<std::string, std::vector<const SessionRecord*>> by_lesson;
    std::map<std::string, const SessionRecord*> last_recorded;
    for (const auto& s : model.recent) {
        if (!by_lesson.count(s.lesson)) order.push_back(s.lesson);
        by_lesson[s.lesson].push_back(&s);
        if (replayable(s)) last_recorded[s.lesson] = &s;
    }
    const float width = ImGui::GetContentRegionAvail().x;
    for (const auto& lesson : order) {
        const auto& all = by_lesson[lesson];
        double best = 0.0;
        for (const auto* s : all) best = std::max(best, s->result.score);
        ImGui::Spacing();
        ImGui::TextUnformatted(lesson_name(model, lesson).c_str());
        const bool demonstrated = std::any_of(all.begin(), all.end(), [](const SessionRecord* s) { return s->kind == "demonstration"; });
        char caption[160];
        std::snprintf(caption, sizeof caption, "last %.0f, best %.0f (%zu session%s%s%s)", all.back()->result.score, best, all.size(), all.size() == 1 ? "" : "s",
                      all.size() > most_shown ? ("; the last " + std::to_string(most_shown) + " drawn").c_str() : "", demonstrated ? "; hollow: a demonstration" : "");
        ImGui::TextDisabled("%s", caption);
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        items.push_back({"result:" + lesson + ": " + caption, {a.x, a.y}, {b.x, b.y}});
        // The last recorded session, to watch again (from the start screen, as a teacher reviews it):
        // beside the caption when it fits, else under it.
        if (const auto it = last_recorded.find(lesson); it != last_recorded.end()) {
            std::string when = iso_utc(it->second->started_unix_s).substr(5, 11); // "11-25T09:47"
            when[5] = ' ';
            char label[96];
            std::snprintf(label, sizeof label, "Replay (%.0f, %s UTC)##%s", it->second->result.score, when.c_str(), lesson.c_str());
            const float button_w = ImGui::CalcTextSize(label, nullptr, true).x + 2.0f * ImGui::GetStyle().FramePadding.x;
            const float after = b.x + ImGui::GetStyle().ItemSpacing.x - ImGui::GetWindowPos().x + button_w;
            if (after <= ImGui::GetWindowContentRegionMax().x) ImGui::SameLine();
            if (tracked_button(items, label, "replay:" + lesson)) replay = it->second->recording;
        }
        const std::vector<const SessionRecord*> shown(all.end() - static_cast<std::ptrdiff_t>(std::min(all.size(), most_shown)), all.end());
        trend(shown, std::min(width, 720.0f));
    }
    const auto& last = model.recent.back();
    ImGui::TextDisabled("last: %s %s, %.1f / 100 (%s)", lesson_name(model, last.lesson).c_str(), iso_utc(last.started_unix_s).substr(0, 10).c_str(), last.result.score,
                        last.kind.c_str());
    return replay;
}

} // namespace

bool tracked_button(std::vector<UiButton>& buttons, const std::string& label, const std::string& name, float width, float height) {
    const bool pressed = ImGui::Button(label.c_str(), ImVec2(width, height));
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    buttons.push_back({name, {a.x, a.y}, {b.x, b.y}});
    return pressed;
}

ButtonRow::ButtonRow(float width) : right_(ImGui::GetCursorScreenPos().x + width) {}

void ButtonRow::place(const char* label, float extra_px) {
    const ImGuiStyle& style = ImGui::GetStyle();
    const float w = ImGui::CalcTextSize(label, nullptr, true).x + 2.0f * style.FramePadding.x + extra_px;
    if (any_ && ImGui::GetItemRectMax().x + style.ItemSpacing.x + w <= right_) ImGui::SameLine();
    any_ = true;
}

TrendLayout trend_layout(const std::vector<const SessionRecord*>& sessions, float width, float label_px) {
    TrendLayout out;
    double lowest = 100.0;
    for (const auto* s : sessions) lowest = std::min(lowest, s->result.score);
    out.floor_score = std::clamp(std::floor(lowest / 10.0) * 10.0 - 10.0, 0.0, 50.0);
    const std::size_t n = sessions.size();
    float next_label_x = 1e30f;
    out.points.resize(n);
    // Labels from the last back, each at least label_px from the one to its right.
    for (std::size_t k = n; k-- > 0;) {
        TrendPoint& p = out.points[k];
        p.x = n == 1 ? 0.5f * width : width * static_cast<float>(k) / static_cast<float>(n - 1);
        p.y = static_cast<float>((std::clamp(sessions[k]->result.score, 0.0, 100.0) - out.floor_score) / (100.0 - out.floor_score));
        p.demonstration = sessions[k]->kind == "demonstration";
        char score[8];
        std::snprintf(score, sizeof score, "%.0f", sessions[k]->result.score);
        p.score = score;
        p.day = iso_utc(sessions[k]->started_unix_s).substr(5, 5);
        p.labelled = next_label_x - p.x >= label_px;
        if (p.labelled) next_label_x = p.x;
    }
    return out;
}

namespace {
// How the scene is shown: a flat screen by default (the whole width for one view), or the stereo
// display the trainee has. Remembered by the app; --stereo fixes it.
void display_choice(StartScreenModel& model, std::vector<UiButton>& buttons) {
    struct Option {
        const char* mode;
        const char* label;
    };
    static constexpr Option options[] = {{"mono", "Flat screen"}, {"sbs", "3D display, side by side"}, {"anaglyph", "Red-cyan glasses"}, {"rows", "3D display, rows"}};
    ButtonRow row(ImGui::GetContentRegionAvail().x);
    row.place("Display:");
    ImGui::TextUnformatted("Display:");
    if (model.display_fixed) ImGui::BeginDisabled();
    for (const auto& o : options) {
        row.place(o.label, ImGui::GetFrameHeight()); // and its circle
        if (ImGui::RadioButton(o.label, model.display == o.mode)) model.display = o.mode;
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        buttons.push_back({std::string("display:") + o.mode, {a.x, a.y}, {b.x, b.y}});
    }
    if (model.display_fixed) {
        ImGui::EndDisabled();
        ImGui::SameLine();
        ImGui::TextDisabled("(set by --stereo)");
    }
}
} // namespace

StartChoice StartScreen::draw(StartScreenModel& model) {
    buttons_.clear();
    StartChoice choice;
    if (!name_loaded_) {
        std::snprintf(name_.data(), name_.size(), "%s", model.trainee.c_str());
        name_loaded_ = true;
    }
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(io.DisplaySize);
    // A scroll bar when one eye's half is too short for it all.
    ImGui::Begin("Ikebana", nullptr, ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                                         ImGuiWindowFlags_NoSavedSettings);
    ImGui::TextUnformatted("Ikebana: practise a school's form, stem by stem");
    ImGui::Separator();
    ImGui::SetNextItemWidth(220.0f);
    // Spaces around the name are dropped; an emptied box keeps the last name (sessions need one).
    if (ImGui::InputText("your name", name_.data(), name_.size())) {
        std::string typed = name_.data();
        typed.erase(0, typed.find_first_not_of(" \t"));
        typed.erase(typed.find_last_not_of(" \t") + 1);
        if (!typed.empty()) model.trainee = typed;
    }
    // Quit at the top right, always in sight.
    ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 60.0f);
    if (tracked_button(buttons_, "Quit", "quit", 60.0f, 0.0f)) choice.kind = StartChoice::Kind::quit;
    display_choice(model, buttons_);
    // What the trainee did last comes first: it is what they come back for.
    if (ImGui::CollapsingHeader("Your last results", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (auto replay = last_results(model, buttons_)) {
            choice.kind = StartChoice::Kind::replay;
            choice.recording = *replay;
        }
    }
    if (!defaulted_) {
        // The lesson practised last, else the first.
        for (std::size_t i = 0; !model.recent.empty() && i < model.lessons.size(); ++i) {
            if (model.lessons[i].id == model.recent.back().lesson) selected_ = i;
        }
        defaulted_ = true;
    }

    const float width = ImGui::GetContentRegionAvail().x;
    const bool wide = width > 860.0f;
    ImGui::Spacing();
    ImGui::TextUnformatted("Lessons");
    if (ImGui::BeginChild("lessons", ImVec2(wide ? 0.3f * width : width, wide ? 0.0f : 24.0f * static_cast<float>(model.lessons.size()) + 8.0f), true)) {
        for (std::size_t i = 0; i < model.lessons.size(); ++i) {
            const auto& l = model.lessons[i];
            const std::string name = l.school + ": " + l.title;
            if (ImGui::Selectable(name.c_str(), selected_ == i)) selected_ = i;
            const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
            buttons_.push_back({"select:" + l.id, {a.x, a.y}, {b.x, b.y}});
        }
    }
    ImGui::EndChild();
    if (wide) ImGui::SameLine();
    ImGui::BeginGroup();
    if (selected_ < model.lessons.size()) {
        const auto& l = model.lessons[selected_];
        const float inner = wide ? 0.68f * width : width;
        // Start first, in sight without scrolling; what the form is follows.
        if (tracked_button(buttons_, "Start this lesson", "start:" + l.id, 180.0f, 30.0f)) {
            choice.kind = StartChoice::Kind::lesson;
            choice.lesson = l.id;
        }
        ImGui::SameLine();
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + inner - 190.0f);
        ImGui::TextUnformatted((l.school + ": " + l.title).c_str());
        ImGui::PopTextWrapPos();
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + inner);
        if (!l.summary.empty()) ImGui::TextDisabled("%s", l.summary.c_str());
        ImGui::PopTextWrapPos();
        if (!l.stems.empty()) form_diagram(l, std::min(inner, 520.0f));
        form_numbers(l);
    }
    ImGui::EndGroup();

    ImGui::Spacing();
    if (ImGui::CollapsingHeader("Hands and controls")) {
        ImGui::Text("left hand: %s", model.hands[0].c_str());
        ImGui::Text("right hand: %s", model.hands[1].c_str());
        ImGui::TextWrapped("Mouse: point at a stem (the cube goes onto it and the whole stem turns yellow) and hold the left button to take it; the wheel "
                           "moves the hand away and nearer along your line of sight; Ctrl+drag leans the held stem as you see it (right: to the "
                           "right, up: away from you), Ctrl+arrows lean it 5 degrees a press, Ctrl+Shift+drag twists it about itself, "
                           "Ctrl+wheel swings its lean round; C cuts it to its role's length; "
                           "Tab switches hands; the arrows turn the view; G shows the form's targets and model; Enter scores; R starts "
                           "over; Esc goes back here. Everything is listed again in the panel beside the scene.");
    }
    ImGui::TextDisabled("%s", model.progress_note.c_str());
    ImGui::End();
    return choice;
}

} // namespace ikebana::game
