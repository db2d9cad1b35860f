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
#include "game/app/start_screen.hpp"
#include "game/app/window_camera.hpp"
#include "game/app/window_stack.hpp"
#include "game/render/offscreen_render.hpp"
#include "game/session/lesson_session.hpp"
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

// The playback and what the window shows of it. Going back opens the recording again.
class Player {
public:
    Player(WindowStack& stack, const ReplayWindowOptions& o) : stack_(stack), o_(o) {}
    // The playback, and a second one that reads the timeline's insertions ahead of it.
    Result<void> open();
    int run(std::uint32_t& presented);

private:
    Result<void> open_playback();
    // Toward `target_us_`, at most `budget_us` of simulated time (the window stays responsive).
    void advance(std::int64_t budget_us);
    void read_timeline(std::int64_t budget_us);
    void panel();
    void timeline_bar(float width);

    WindowStack& stack_;
    const ReplayWindowOptions& o_;
    std::vector<TimelineMark> marks_;
    std::unique_ptr<SessionPlayback> playback_;
    std::unique_ptr<SessionPlayback> timeline_; // null once it has been read to the end
    InsertionWatcher insertions_;
    std::int64_t target_us_ = 0;
    std::optional<FormScore> replayed_score_;
    std::int64_t end_us_ = 0;
    double play_us_ = 0.0; // where the playback is asked to be (fractions of a microsecond kept)
    double speed_ = 1.0;
    bool paused_ = false;
    bool back_ = false;
    WindowCamera camera_; // the reviewer's: any side, whatever way the trainee looked
    std::vector<UiButton> buttons_;
    std::optional<std::int64_t> jump_to_;
    float scrub_s_ = 0.0f;   // the slider's value while it is dragged
    bool scrubbing_ = false;
};

Result<void> Player::open() {
    auto t = SessionPlayback::open(o_.folder);
    if (!t) return std::move(t).error();
    timeline_ = std::move(t).value();
    marks_ = recorded_marks(*timeline_);
    return open_playback();
}

// The insertions are seen by playing the recording: a second playback runs ahead, a simulated second
// or so a frame, and its marks join the cuts' and tilts' as it goes.
void Player::read_timeline(std::int64_t budget_us) {
    if (!timeline_) return;
    timeline_->run_until(std::min(end_us_, timeline_->now_us() + budget_us));
    std::vector<TimelineMark> seen;
    insertions_.watch(timeline_->world().main.resource<const systems::ReceivedFrames>()->latest(), seen);
    for (auto& m : seen) {
        const auto at = std::upper_bound(marks_.begin(), marks_.end(), m.at_us, [](std::int64_t t, const TimelineMark& k) { return t < k.at_us; });
        marks_.insert(at, std::move(m));
    }
    if (timeline_->now_us() >= end_us_) timeline_.reset();
}

Result<void> Player::open_playback() {
    auto p = SessionPlayback::open(o_.folder);
    if (!p) return std::move(p).error();
    playback_ = std::move(p).value();
    end_us_ = playback_->info().end_us;
    replayed_score_.reset();
    auto& hud = *playback_->world().main.resource<components::HudInfo>();
    hud.title = "REPLAY";
    hud.keys = "Space: pause   arrows/right-drag: look around   Esc: back";
    for (std::size_t h = 0; h < 2; ++h) hud.device[h] = playback_->samples(h).empty() ? "no device" : "as recorded";
    return {};
}

// Forward: the clock runs on (scoring on the way, as the session did). Back: the recording is
// opened again and runs from its start, a budget a frame, until it is there.
void Player::advance(std::int64_t budget_us) {
    target_us_ = std::clamp<std::int64_t>(target_us_, 0, end_us_);
    if (target_us_ < playback_->now_us()) {
        if (auto again = open_playback(); !again) {
            std::cerr << "ikebana replay: " << again.error().message << "\n";
            back_ = true; // the recording went away under the window: nothing more to show
            return;
        }
    }
    const std::int64_t to = std::min(target_us_, playback_->now_us() + budget_us);
    const std::int64_t scored = playback_->info().scored_us;
    if (playback_->now_us() < scored && scored <= to) {
        playback_->run_until(scored);
        if (auto frame = playback_->scored_frame(); frame) {
            if (auto s = playback_->score(**frame); s) replayed_score_ = std::move(s).value();
        }
    }
    playback_->run_until(to);
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
        for (const auto& m : marks_) {
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
    for (const auto& m : marks_) draw->AddLine(ImVec2(x_of(m.at_us), at.y), ImVec2(x_of(m.at_us), at.y + h), mark_colour(m.kind), 3.0f);
    const float now_x = x_of(playback_->now_us());
    draw->AddTriangleFilled(ImVec2(now_x - 5.0f, at.y), ImVec2(now_x + 5.0f, at.y), ImVec2(now_x, at.y + 7.0f), IM_COL32(255, 255, 255, 255));
}

void Player::panel() {
    buttons_.clear();
    const ImGuiIO& io = ImGui::GetIO();
    // A strip along the bottom, over the table's front edge: the arrangement stays in sight.
    const float w = io.DisplaySize.x - 16.0f;
    const float h = std::min(165.0f, 0.27f * io.DisplaySize.y);
    ImGui::SetNextWindowPos(ImVec2(8.0f, io.DisplaySize.y - h - 4.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(w, h));
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::Begin("replay", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
    const SessionInfo& info = playback_->info();
    ImGui::Text("Replay: %s (%s)", playback_->lesson().title.c_str(), info.kind.c_str());
    ImGui::SameLine();
    ImGui::TextDisabled("  %.1f s of %.1f s, x%.2g", static_cast<double>(playback_->now_us()) * 1e-6, static_cast<double>(end_us_) * 1e-6, speed_);
    if (tracked_button(buttons_, paused_ ? "Play (Space)" : "Pause (Space)", "play", 110.0f)) paused_ = !paused_;
    for (double s : speeds) {
        ImGui::SameLine();
        char label[16];
        std::snprintf(label, sizeof label, "x%g", s);
        if (tracked_button(buttons_, label, std::string("speed:") + label)) speed_ = s;
    }
    ImGui::SameLine();
    if (tracked_button(buttons_, "From the start", "restart")) jump_to_ = 0;
    ImGui::SameLine();
    if (tracked_button(buttons_, "Back (Esc)", "back")) back_ = true;
    const float bar = ImGui::GetContentRegionAvail().x;
    timeline_bar(bar);
    // Dragged, the slider only shows where it will go; let go, the playback goes there (going back
    // plays the recording again from its start, once, not at every step of the drag).
    if (!scrubbing_) scrub_s_ = static_cast<float>(static_cast<double>(playback_->now_us()) * 1e-6);
    ImGui::SetNextItemWidth(bar);
    ImGui::SliderFloat("##time", &scrub_s_, 0.0f, static_cast<float>(static_cast<double>(end_us_) * 1e-6), "%.1f s");
    scrubbing_ = ImGui::IsItemActive();
    if (ImGui::IsItemDeactivatedAfterEdit()) jump_to_ = static_cast<std::int64_t>(static_cast<double>(scrub_s_) * 1e6);
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    buttons_.push_back({"timeline", {a.x, a.y}, {b.x, b.y}});
    // The marks one after another: the last one passed and the next, each a jump to a second before it.
    const std::int64_t now = playback_->now_us();
    const TimelineMark* before = nullptr;
    const TimelineMark* after = nullptr;
    for (const auto& m : marks_) {
        if (m.at_us < now + 1'000'000) before = &m; // (now stands a second before a mark it jumped to)
        else if (!after && m.at_us > now + 1'000'000) after = &m;
    }
    if (tracked_button(buttons_, "< previous", "mark:previous") && before) jump_to_ = std::max<std::int64_t>(0, before->at_us - 1'000'000);
    ImGui::SameLine();
    if (tracked_button(buttons_, "next >", "mark:next") && after) jump_to_ = std::max<std::int64_t>(0, after->at_us - 1'000'000);
    ImGui::SameLine();
    if (after) {
        ImGui::PushStyleColor(ImGuiCol_Text, mark_colour(after->kind));
        ImGui::Text("next: %.1f s %s", static_cast<double>(after->at_us) * 1e-6, after->what.c_str());
        ImGui::PopStyleColor();
    } else {
        ImGui::TextDisabled(marks_.empty() ? "no cut, tilt or insertion in this session" : "no mark after this");
    }
    // The score as it was given, and as this playback reached it.
    ImGui::Text("Scored %.1f / 100 at %.1f s", info.score, static_cast<double>(info.scored_us) * 1e-6);
    if (replayed_score_) {
        ImGui::SameLine();
        const bool same = std::abs(replayed_score_->score - info.score) < 1e-6;
        ImGui::TextColored(same ? ImVec4(0.5f, 0.9f, 0.5f, 1.0f) : ImVec4(1.0f, 0.5f, 0.4f, 1.0f), same ? "  (replayed: the same)" : "  (replayed: %.1f, not the same)",
                           replayed_score_->score);
    }
    ImGui::SameLine();
    // While the playback catches up or the insertions are still being read, that; else the legend.
    if (playback_->now_us() < target_us_) {
        ImGui::TextColored(ImVec4(0.75f, 0.4f, 0.0f, 1.0f), "   going to %.1f s", static_cast<double>(target_us_) * 1e-6);
    } else if (timeline_) {
        ImGui::TextDisabled("   reading the insertions: %.0f %%", 100.0 * static_cast<double>(timeline_->now_us()) / static_cast<double>(std::max<std::int64_t>(1, end_us_)));
    } else {
        ImGui::TextDisabled("   cuts red, tilts blue, insertions green");
    }
    ImGui::End();
}

int Player::run(std::uint32_t& presented) {
    speed_ = o_.speed;
    const render::StereoRig base = rig_of(playback_->display());
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
        if (auto* ui = stack_.ui()) {
            ui->begin_frame(stack_.mode());
            if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Space), false)) paused_ = !paused_;
            panel();
            ui->end_frame();
        }
        // About a simulated second a frame for catching up (a jump, going back) and as much for the
        // timeline: on this machine the simulation runs about 12 times real time.
        constexpr std::int64_t catch_up_us = 1'000'000;
        const bool catching_up = playback_->now_us() < target_us_;
        if (jump_to_) {
            target_us_ = *jump_to_;
            play_us_ = static_cast<double>(std::clamp<std::int64_t>(*jump_to_, 0, end_us_));
            jump_to_.reset();
        } else if (!paused_ && !scrubbing_ && !catching_up && playback_->now_us() < end_us_) {
            play_us_ = std::min(static_cast<double>(end_us_), play_us_ + dt * speed_ * 1e6);
            target_us_ = static_cast<std::int64_t>(play_us_);
        }
        advance(catch_up_us);
        read_timeline(catch_up_us);
        const auto& prepared = *playback_->world().main.resource<const components::PreparedFrame>();
        stack_.renderer().set_overlay(prepared.overlay);
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
            take_snapshot(state, playback_->world().main.resource<const systems::ReceivedFrames>()->latest());
            state.buttons.clear();
            for (const auto& b : buttons_) state.buttons.push_back({b.label, b.min_px, b.max_px});
            state.results = replayed_score_ ? 1 : 0;
            state.result_json = replayed_score_ ? replayed_score_->json(-1) : "";
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
    auto stack = WindowStack::open(std::move(window).value(), {.width = o.width, .height = o.height, .mode = render::StereoMode::side_by_side, .validation = o.validation, .need_ui = true, .msaa = 0});
    if (!stack) {
        std::cerr << "ikebana replay: " << stack.error().message << "\n";
        return 3;
    }
    std::uint32_t presented = 0;
    return play_recording(**stack, o, presented);
}

} // namespace ikebana::game
