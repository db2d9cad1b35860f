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

constexpr double deg = 3.14159265358979323846 / 180.0;

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

// Returns the recording to replay when its button is pressed.
std::optional<std::string> last_results(const StartScreenModel& model, std::vector<UiButton>& items) {
    std::optional<std::string> replay;
    if (model.recent.empty()) {
        ImGui::TextDisabled("No results yet: a lesson's Enter scores it and keeps the score here.");
        return replay;
    }
    // Each lesson's scores in order, as a small plot, with the last and the best.
    std::vector<std::string> order;
    std::map<std::string, std::vector<float>> scores;
    std::map<std::string, const SessionRecord*> last_recorded;
    for (const auto& s : model.recent) {
        if (!scores.count(s.lesson)) order.push_back(s.lesson);
        scores[s.lesson].push_back(static_cast<float>(s.result.score));
        if (replayable(s)) last_recorded[s.lesson] = &s;
    }
    for (const auto& lesson : order) {
        const auto& v = scores[lesson];
        const float best = *std::max_element(v.begin(), v.end());
        char caption[200];
        std::snprintf(caption, sizeof caption, "%s: last %.0f, best %.0f (%zu session%s)", lesson.c_str(), v.back(), best, v.size(), v.size() == 1 ? "" : "s");
        ImGui::TextUnformatted(caption);
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        items.push_back({std::string("result:") + caption, {a.x, a.y}, {b.x, b.y}});
        // The last recorded session, to watch again (from the start screen, as a teacher reviews it).
        if (const auto it = last_recorded.find(lesson); it != last_recorded.end()) {
            ImGui::SameLine();
            char label[96];
            std::string when = iso_utc(it->second->started_unix_s).substr(5, 11); // "11-25T09:47"
            when[5] = ' ';
            std::snprintf(label, sizeof label, "Replay (%.0f, %s UTC)##%s", it->second->result.score, when.c_str(), lesson.c_str());
            if (tracked_button(items, label, "replay:" + lesson)) replay = it->second->recording;
        }
        // The trend, once there is one (0 to 100).
        if (v.size() >= 2)
            ImGui::PlotLines(("##" + lesson).c_str(), v.data(), static_cast<int>(v.size()), 0, nullptr, 0.0f, 100.0f,
                             ImVec2(ImGui::GetContentRegionAvail().x, 36.0f));
    }
    const auto& last = model.recent.back();
    ImGui::TextDisabled("last: %s %s, %.0f / 100 (%s)", last.lesson.c_str(), iso_utc(last.started_unix_s).substr(0, 10).c_str(), last.result.score,
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

namespace {
// How the scene is shown: a flat screen by default (the whole width for one view), or the stereo
// display the trainee has. Remembered by the app; --stereo fixes it.
void display_choice(StartScreenModel& model, std::vector<UiButton>& buttons) {
    struct Option {
        const char* mode;
        const char* label;
    };
    static constexpr Option options[] = {{"mono", "Flat screen"}, {"sbs", "3D display, side by side"}, {"anaglyph", "Red-cyan glasses"}, {"rows", "3D display, rows"}};
    ImGui::TextUnformatted("Display:");
    if (model.display_fixed) ImGui::BeginDisabled();
    for (const auto& o : options) {
        ImGui::SameLine();
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
        ImGui::TextWrapped("Mouse: move the cube onto a stem (the whole stem turns yellow) and hold the left button to take it; the wheel "
                           "moves the hand away and nearer; Ctrl+drag leans the held stem as you see it (right: to the right, up: away from "
                           "you), Ctrl+arrows lean it 5 degrees a press, Ctrl+wheel swings its lean round; C cuts it to its role's length; "
                           "Tab switches hands; the arrows turn the view; G shows the form's targets and model; Enter scores; R starts "
                           "over; Esc goes back here. Everything is listed again in the panel beside the scene.");
    }
    ImGui::TextDisabled("%s", model.progress_note.c_str());
    ImGui::End();
    return choice;
}

} // namespace ikebana::game
