#include "game/app/replay_window.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>
#include <unistd.h>

#include <imgui.h>

#include "components/presentation.hpp"
#include "engine/render/screen_layout.hpp"
#include "game/app/session_panel.hpp"
#include "game/app/start_screen.hpp"
#include "game/app/window_camera.hpp"
#include "game/app/window_stack.hpp"
#include "game/render/offscreen_render.hpp"
#include "game/session/lesson_session.hpp"
#include "game/session/seekable_playback.hpp"
#include "game/session/session_timeline.hpp"
#include "game/session/window_state.hpp"
#include "game/world/world.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::game {

namespace {

constexpr double speeds[] = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0};

ImU32 mark_colour(TimelineMark::Kind k) {
    switch (k) {
    case TimelineMark::Kind::cut: return IM_COL32(230, 90, 60, 255);
    case TimelineMark::Kind::tilt: return IM_COL32(80, 150, 230, 255);
    case TimelineMark::Kind::insertion: return IM_COL32(90, 190, 90, 255);
    }
    return IM_COL32(200, 200, 200, 255);
}

// The playback and what the window shows of it (game/session/seekable_playback.hpp: moments kept
// by a second playback reading ahead, so that any point is a jump and a few seconds' play away).
class Player {
public:
    Player(WindowStack& stack, const ReplayWindowOptions& o) : stack_(stack), o_(o) {}
    Result<void> open();
    int run(std::uint32_t& presented);

private:
    void panel(float left_px, float width_px, const std::vector<std::string>& hud_lines);
    void timeline_bar(float width);
    [[nodiscard]] SessionPlayback& playback() { return seek_->shown(); }

    WindowStack& stack_;
    const ReplayWindowOptions& o_;
    std::unique_ptr<SeekablePlayback> seek_;
    std::int64_t end_us_ = 0;
    double play_us_ = 0.0; // where the playback is asked to be (fractions of a microsecond kept)
    double speed_ = 1.0;
    bool paused_ = false;
    bool back_ = false;
    WindowCamera camera_; // the reviewer's: any side, whatever way the trainee looked
    std::vector<UiButton> buttons_;
    std::vector<WindowState::Box> panels_; // where the column is, for the window's layout report
    std::optional<std::int64_t> jump_to_;
    float scrub_s_ = 0.0f;   // the slider's value while it is dragged
    bool scrubbing_ = false;
};

Result<void> Player::open() {
    auto s = SeekablePlayback::open(o_.folder);
    if (!s) return std::move(s).error();
    seek_ = std::move(s).value();
    end_us_ = seek_->end_us();
    auto& hud = *playback().world().main.resource<components::HudInfo>();
    hud.title = "REPLAY";
    hud.keys = "Space: pause   arrows/right-drag: look around   Esc: back";
    for (std::size_t h = 0; h < 2; ++h) hud.device[h] = playback().samples(h).empty() ? "no device" : "as recorded";
    return {};
}

// Above the slider: the session's length with each mark as a tick in its colour. A click on the bar
// goes a second before the mark nearest to it (within a few pixels), else to that moment.
void Player::timeline_bar(float width) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float h = 14.0f;
    const double end = static_cast<double>(std::max<std::int64_t>(1, end_us_));
    const auto x_of = [&](std::int64_t t) { return at.x + width * static_cast<float>(static_cast<double>(t) / end); };
    if (ImGui::InvisibleButton("##marks", ImVec2(width, h))) {
        const float x = ImGui::GetIO().MousePos.x;
        std::int64_t to = static_cast<std::int64_t>(static_cast<double>((x - at.x) / width) * end);
        float nearest = 6.0f;
        for (const auto& m : seek_->marks()) {
            if (std::abs(x_of(m.at_us) - x) < nearest) {
                nearest = std::abs(x_of(m.at_us) - x);
                to = std::max<std::int64_t>(0, m.at_us - 1'000'000);
            }
        }
        jump_to_ = to;
    }
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    buttons_.push_back({"marks", {a.x, a.y}, {b.x, b.y}});
    draw->AddRectFilled(at, ImVec2(at.x + width, at.y + h), IM_COL32(60, 60, 60, 255), 3.0f);
    for (const auto& m : seek_->marks()) draw->AddLine(ImVec2(x_of(m.at_us), at.y), ImVec2(x_of(m.at_us), at.y + h), mark_colour(m.kind), 3.0f);
    const float now_x = x_of(seek_->now_us());
    draw->AddTriangleFilled(ImVec2(now_x - 5.0f, at.y), ImVec2(now_x + 5.0f, at.y), ImVec2(now_x, at.y + 7.0f), IM_COL32(255, 255, 255, 255));
}

// The column right of the scene (render::ScreenLayout keeps it free of the 3D view, as the lesson's
// panel does): nothing of the arrangement or the table is covered. Top down: what is played and where,
// the controls, the timeline and its marks, the score, then what the heads-up text says.
void Player::panel(float left_px, float width_px, const std::vector<std::string>& hud_lines) {
    buttons_.clear();
    panels_.clear();
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(left_px, 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(width_px, io.DisplaySize.y), ImGuiCond_Always);
    ImGui::Begin("replay", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
    ImGui::PushTextWrapPos(0.0f);
    const SessionInfo& info = playback().info();
    ImGui::TextWrapped("Replay: %s (%s)", playback().lesson().title.c_str(), info.kind.c_str());
    ImGui::Text("%.1f s of %.1f s, x%g", static_cast<double>(playback().now_us()) * 1e-6, static_cast<double>(end_us_) * 1e-6, speed_);
    const float full = ImGui::GetContentRegionAvail().x;
    if (tracked_button(buttons_, paused_ ? "Play (Space)" : "Pause (Space)", "play", full)) paused_ = !paused_;
    {
        ButtonRow row(full);
        for (double sp : speeds) {
            char label[16];
            std::snprintf(label, sizeof label, "x%g", sp);
            row.place(label);
            if (tracked_button(buttons_, label, std::string("speed:") + label)) speed_ = sp;
        }
    }
    ImGui::Separator();
    timeline_bar(full);
    // Dragged, the slider only shows where it will go; let go, the playback goes there (once, not at
    // every step of the drag).
    if (!scrubbing_) scrub_s_ = static_cast<float>(static_cast<double>(playback().now_us()) * 1e-6);
    ImGui::SetNextItemWidth(full);
    ImGui::SliderFloat("##time", &scrub_s_, 0.0f, static_cast<float>(static_cast<double>(end_us_) * 1e-6), "%.1f s");
    scrubbing_ = ImGui::IsItemActive();
    if (ImGui::IsItemDeactivatedAfterEdit()) jump_to_ = static_cast<std::int64_t>(static_cast<double>(scrub_s_) * 1e6);
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    buttons_.push_back({"timeline", {a.x, a.y}, {b.x, b.y}});
    // The marks one after another: the last one passed and the next, each a jump to a second before it.
    const std::int64_t now = playback().now_us();
    const TimelineMark* before = nullptr;
    const TimelineMark* after = nullptr;
    for (const auto& m : seek_->marks()) {
        if (m.at_us < now + 1'000'000) before = &m; // (now stands a second before a mark it jumped to)
        else if (!after && m.at_us > now + 1'000'000) after = &m;
    }
    {
        ButtonRow row(full);
        row.place("< previous");
        if (tracked_button(buttons_, "< previous", "mark:previous") && before) jump_to_ = std::max<std::int64_t>(0, before->at_us - 1'000'000);
        row.place("next >");
        if (tracked_button(buttons_, "next >", "mark:next") && after) jump_to_ = std::max<std::int64_t>(0, after->at_us - 1'000'000);
    }
    if (after) {
        ImGui::PushStyleColor(ImGuiCol_Text, mark_colour(after->kind));
        ImGui::TextWrapped("next: %.1f s %s", static_cast<double>(after->at_us) * 1e-6, after->what.c_str());
        ImGui::PopStyleColor();
    } else {
        ImGui::TextDisabled(seek_->marks().empty() ? "no cut, tilt or insertion in this session" : "no mark after this");
    }
    // While the playback goes somewhere or the insertions are still being read, that; else the legend.
    if (!seek_->arrived()) {
        ImGui::TextColored(ImVec4(0.95f, 0.6f, 0.2f, 1.0f), "going to %.1f s", static_cast<double>(seek_->target_us()) * 1e-6);
    } else if (seek_->read_fraction() < 1.0) {
        ImGui::TextDisabled("reading the insertions: %.0f %%", 100.0 * seek_->read_fraction());
    } else {
        const TimelineMark::Kind kinds[] = {TimelineMark::Kind::cut, TimelineMark::Kind::tilt, TimelineMark::Kind::insertion};
        const char* names[] = {"cuts", "tilts", "insertions"};
        ButtonRow row(full);
        for (int k = 0; k < 3; ++k) {
            row.place(names[k]);
            ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(mark_colour(kinds[k])), "%s", names[k]);
        }
    }
    ImGui::Separator();
    // The score as it was given, and as this playback reached it.
    ImGui::TextWrapped("Scored %.1f / 100 at %.1f s", info.score, static_cast<double>(info.scored_us) * 1e-6);
    if (const auto& replayed_score = seek_->replayed_score()) {
        const bool same = std::abs(replayed_score->score - info.score) < 1e-6;
        ImGui::TextColored(same ? ImVec4(0.5f, 0.9f, 0.5f, 1.0f) : ImVec4(1.0f, 0.5f, 0.4f, 1.0f), same ? "replayed: the same" : "replayed: %.1f, not the same",
                           replayed_score->score);
    }
    {
        ButtonRow row(full);
        row.place("From the start");
        if (tracked_button(buttons_, "From the start", "restart")) jump_to_ = 0;
        row.place("Back (Esc)");
        if (tracked_button(buttons_, "Back (Esc)", "back")) back_ = true;
    }
    ImGui::Separator();
    for (const auto& line : hud_lines) ImGui::TextDisabled("%s", line.c_str());
    ImGui::PopTextWrapPos();
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    panels_.push_back({"replay", 0, {at.x, at.y}, {size.x, size.y}});
    ImGui::End();
}

int Player::run(std::uint32_t& presented) {
    speed_ = o_.speed;
    const render::StereoRig base = rig_of(playback().display());
    camera_.reset(base);
    auto last = std::chrono::steady_clock::now();
    WindowState state;
    state.screen = "replay";
    auto& window = stack_.window();
    stack_.pointer().forget_taps();
    while (!back_) {
        window.poll_events();
        if (window.should_close()) break;
        const platform::PointerState in = stack_.pointer().read();
        if (in.quit_key) break;
        const auto now = std::chrono::steady_clock::now();
        const double dt = std::min(0.1, std::chrono::duration<double>(now - last).count());
        last = now;
        camera_.turn(in);
        // The column beside each eye's scene, as the lesson's (none without Dear ImGui: the heads-up
        // text is then drawn over the scene). The heads-up lines go in it; labels on things stay on them.
        const render::ScreenLayout whole{stack_.mode(), glm::dvec2{std::max(1.0, in.window_px.x), std::max(1.0, in.window_px.y)}, 0.0};
        const double column_px = stack_.ui() ? std::floor(session_column_px(whole.area_width_px())) : 0.0;
        stack_.renderer().set_column(static_cast<std::uint32_t>(column_px));
        const auto& shown = *playback().world().main.resource<const components::PreparedFrame>();
        std::vector<std::string> hud_lines;
        for (const auto& o : shown.overlay) {
            if (!o.anchor_m) hud_lines.insert(hud_lines.end(), o.lines.begin(), o.lines.end());
        }
        if (auto* ui = stack_.ui()) {
            ui->begin_frame(stack_.mode());
            if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Space), false)) paused_ = !paused_;
            panel(static_cast<float>(whole.area_width_px() - column_px), static_cast<float>(column_px), hud_lines);
            ui->end_frame();
        }
        // About 60 ms of each frame, in quarter-seconds of simulated time: the playback's first (a
        // jump plays at most the 5 s from the moment before it), the rest reading ahead. The simulation
        // runs about 50 times real time here, so a jump takes a frame or two and the window stays
        // responsive.
        constexpr std::int64_t piece_us = 250'000;
        constexpr auto frame_budget = std::chrono::milliseconds(60);
        if (jump_to_) {
            seek_->go_to(*jump_to_);
            play_us_ = static_cast<double>(seek_->target_us());
            jump_to_.reset();
        } else if (!paused_ && !scrubbing_ && seek_->arrived() && seek_->now_us() < end_us_) {
            play_us_ = std::min(static_cast<double>(end_us_), play_us_ + dt * speed_ * 1e6);
            seek_->go_to(static_cast<std::int64_t>(play_us_));
        }
        const auto stepping = std::chrono::steady_clock::now();
        do {
            seek_->step(piece_us);
        } while (std::chrono::steady_clock::now() - stepping < frame_budget && !(seek_->arrived() && seek_->read_fraction() >= 1.0));
        const auto& prepared = *playback().world().main.resource<const components::PreparedFrame>();
        if (stack_.ui()) {
            std::vector<render::OverlayPanel> labels;
            for (const auto& o : prepared.overlay) {
                if (o.anchor_m) labels.push_back(o);
            }
            stack_.renderer().set_overlay(std::move(labels));
        } else {
            stack_.renderer().set_overlay(prepared.overlay);
        }
        const bool want_shot = !o_.screenshot.empty() && o_.frames > 0 && presented + 1 >= o_.frames;
        auto frame = stack_.present(prepared.list, camera_.rig(), want_shot);
        if (!frame) {
            std::cerr << "ikebana replay: " << frame.error().message << "\n";
            return 3;
        }
        if (*frame && (*frame)->presented) ++presented;
        if (*frame && (*frame)->screenshot) {
            if (auto written = render::write_png(o_.screenshot, *(*frame)->screenshot); !written) std::cerr << "ikebana replay: " << written.error().message << "\n";
            else std::printf("ikebana replay: screenshot in %s\n", o_.screenshot.c_str());
        }
        if (!*frame) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (!o_.state_out.empty()) {
            state.frame += 1;
            state.window_px = in.window_px;
            state.cursor_px = in.cursor_px;
            take_snapshot(state, playback().world().main.resource<const systems::ReceivedFrames>()->latest());
            state.buttons.clear();
            for (const auto& b : buttons_) state.buttons.push_back({b.label, b.min_px, b.max_px});
            take_layout(state, PointerView{camera_.rig(), stack_.mode(), camera_.yaw_rad(), column_px}, whole.window_px,
                        playback().world().main.resource<const systems::ReceivedFrames>()->latest(), panels_);
            const auto& replayed_score = seek_->replayed_score();
            state.results = replayed_score ? 1 : 0;
            state.result_json = replayed_score ? replayed_score->json(-1) : "";
            if (auto written = write_window_state(o_.state_out, state); !written) {
                std::cerr << "ikebana replay: --state-out: " << written.error().message << "\n";
                return 2;
            }
        }
        if (o_.frames > 0 && presented >= o_.frames) break;
    }
    vkDeviceWaitIdle(stack_.vulkan().device());
    return 0;
}

} // namespace

int play_recording(WindowStack& stack, const ReplayWindowOptions& o, std::uint32_t& presented) {
    Player player(stack, o);
    if (auto opened = player.open(); !opened) {
        std::cerr << "ikebana replay: " << opened.error().message << "\n";
        return 2;
    }
    return player.run(presented);
}

int run_replay_window(const ReplayWindowOptions& o) {
    const auto mode = render::parse_stereo_mode(o.stereo);
    if (!mode) {
        std::cerr << "ikebana replay: --stereo: " << mode.error().message << "\n";
        return 2;
    }
    // Read before a window opens: a bad folder is an error with or without a display.
    {
        auto check = SessionPlayback::open(o.folder);
        if (!check) {
            std::cerr << "ikebana replay: " << check.error().message << "\n";
            return 2;
        }
    }
    auto window = platform::Window::create("Ikebana: replay", o.width, o.height);
    if (!window) {
        std::cerr << "ikebana replay: " << window.error().message << "; `ikebana replay " << o.folder << " --json -` replays it without a window\n";
        return 3;
    }
    auto stack = WindowStack::open(std::move(window).value(), {.width = o.width, .height = o.height, .mode = *mode, .validation = o.validation, .need_ui = true, .msaa = 0});
    if (!stack) {
        std::cerr << "ikebana replay: " << stack.error().message << "\n";
        return 3;
    }
    std::uint32_t presented = 0;
    return play_recording(**stack, o, presented);
}

} // namespace ikebana::game
