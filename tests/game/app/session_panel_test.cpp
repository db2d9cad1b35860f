// The lesson's panel, drawn by Dear ImGui without a window (issue 37: the panel scrolled its Next line
// out of view, and the wheel did not scroll it while a stem was held).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include <imgui.h>

#include "game/app/session_panel.hpp"

using namespace ikebana::game;

namespace {
struct HeadlessUi {
    HeadlessUi() {
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.DisplaySize = ImVec2(1280.0f, 720.0f);
        io.DeltaTime = 1.0f / 30.0f;
        io.IniFilename = nullptr;
        unsigned char* pixels = nullptr;
        int w = 0, h = 0;
        io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    }
    ~HeadlessUi() { ImGui::DestroyContext(); }
    HeadlessUi(const HeadlessUi&) = delete;
    HeadlessUi& operator=(const HeadlessUi&) = delete;
    // One frame with the mouse at `at`, the left button as given and `wheel` notches.
    void frame(SessionPanel& panel, const SessionPanelModel& model, ImVec2 at, bool left_down, float wheel) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = at;
        io.MouseDown[0] = left_down;
        io.MouseWheel = wheel;
        ImGui::NewFrame();
        (void)panel.draw(model, 880.0f, 400.0f);
        ImGui::Render();
    }
};

double top_of(const SessionPanel& panel, const std::string& label) {
    const auto& b = panel.buttons();
    const auto it = std::find_if(b.begin(), b.end(), [&](const UiButton& u) { return u.label == label; });
    return it == b.end() ? -1.0 : it->min_px.y;
}
} // namespace

TEST(SessionPanel, TheNextStepStaysInViewAndTheWheelScrollsWhatIsBelowItEvenWithAStemHeld) {
    HeadlessUi ui;
    SessionPanel panel;
    SessionPanelModel model;
    model.title = "Sogetsu: Basic Upright Style";
    model.next_step = "scored: the bars below show each stem";
    model.holding = true;
    model.score = 62.0;
    for (const char* role : {"shin", "soe", "hikae"}) {
        SessionPanelModel::StemResult s;
        s.role = role;
        for (int i = 0; i < 4; ++i) s.bars.push_back({"tilt 0.0 / 14", 0.0f, "61° from vertical, the form wants 75° ±10°, 4° outside it: lean it 14° more toward the right front"});
        model.stems.push_back(s);
    }
    for (int i = 0; i < 6; ++i) model.rules.push_back("to do: the kenzan shows from the front: add a low supporting stem leaning toward you, in front of its left end");
    // The left button went down in the scene (a stem taken) and stays down as the cursor goes over the panel.
    ui.frame(panel, model, ImVec2(300.0f, 300.0f), true, 0.0f);
    ui.frame(panel, model, ImVec2(1000.0f, 500.0f), true, 0.0f);
    const double finish = top_of(panel, "finish"), report = top_of(panel, "report");
    ASSERT_GE(finish, 0.0);
    ASSERT_GE(report, 0.0);
    for (int i = 0; i < 3; ++i) ui.frame(panel, model, ImVec2(1000.0f, 500.0f), true, -3.0f);
    ui.frame(panel, model, ImVec2(1000.0f, 500.0f), true, 0.0f);
    EXPECT_DOUBLE_EQ(top_of(panel, "finish"), finish) << "the buttons under the Next line stay";
    EXPECT_LT(top_of(panel, "report"), report - 50.0) << "what is below them scrolled up";
    // The wheel over the scene does not scroll the panel.
    const double scrolled = top_of(panel, "report");
    for (int i = 0; i < 3; ++i) ui.frame(panel, model, ImVec2(300.0f, 300.0f), true, 3.0f);
    ui.frame(panel, model, ImVec2(300.0f, 300.0f), true, 0.0f);
    EXPECT_DOUBLE_EQ(top_of(panel, "report"), scrolled);
    // Let go, and a stem taken again: what is said of it comes back into view (scrolled down, the
    // result had hidden the held stem's lines and its lean buttons above).
    model.holding = false;
    ui.frame(panel, model, ImVec2(1000.0f, 500.0f), false, 0.0f);
    model.holding = true;
    ui.frame(panel, model, ImVec2(300.0f, 300.0f), true, 0.0f);
    ui.frame(panel, model, ImVec2(300.0f, 300.0f), true, 0.0f);
    EXPECT_GT(top_of(panel, "tilt:left"), top_of(panel, "finish")) << "the lean buttons below the fixed ones, in view";
    EXPECT_GT(top_of(panel, "report"), scrolled) << "scrolled back to the top";
}
