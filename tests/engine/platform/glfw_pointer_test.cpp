#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

#include <GLFW/glfw3.h>

#include "engine/platform/pointer_input.hpp"

using namespace ikebana::platform;

namespace {
// GLFW started once for the whole process and left running: started again right after
// glfwTerminate, it now and then fails on X ("GLFW cannot start here" in CI).
bool glfw_ready() {
    static const bool ready = glfwInit() == GLFW_TRUE;
    return ready;
}
} // namespace

// A real window (under Xvfb in CI; skipped where there is no display).
TEST(GlfwPointer, ReadsTheCursorOfARealWindow) {
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display) GTEST_SKIP() << "no display (ctest runs this under xvfb-run)";
    if (!glfw_ready()) GTEST_SKIP() << "GLFW cannot start here";
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(320, 240, "ikebana pointer test", nullptr, nullptr);
    ASSERT_NE(window, nullptr);
    {
        GlfwPointerSource pointer(window);
        glfwSetCursorPos(window, 100.0, 50.0);
        for (int i = 0; i < 10; ++i) glfwPollEvents();
        const auto s = pointer.read();
        EXPECT_NEAR(s.cursor_px.x, 100.0, 1.0);
        EXPECT_NEAR(s.cursor_px.y, 50.0, 1.0);
        EXPECT_EQ(s.window_px, glm::dvec2(320, 240));
        EXPECT_FALSE(s.grab_button);
        EXPECT_FALSE(s.switch_hand);
    }
    glfwDestroyWindow(window);
}

TEST(KeyTaps, ATapBetweenTwoReadingsIsReadOnce) {
    KeyTaps c;
    EXPECT_FALSE(c.report());
    c.press();
    c.release(); // down and up before the frame read it
    EXPECT_TRUE(c.report());
    EXPECT_FALSE(c.report());
    EXPECT_FALSE(c.report());
}

TEST(KeyTaps, TwoTapsInOneFrameAreTwoPressesWithAnUpBetween) {
    KeyTaps c;
    c.press();
    c.release();
    c.press();
    c.release();
    std::vector<bool> readings;
    for (int i = 0; i < 5; ++i) readings.push_back(c.report());
    EXPECT_EQ(readings, (std::vector<bool>{true, false, true, false, false}));
}

TEST(KeyTaps, AHeldKeyIsDownUntilItIsLetGo) {
    KeyTaps ctrl;
    ctrl.press();
    EXPECT_TRUE(ctrl.report());
    EXPECT_TRUE(ctrl.report());
    EXPECT_TRUE(ctrl.report());
    ctrl.release();
    EXPECT_FALSE(ctrl.report());
}

// GLFW's key events reach the reading (the window's own callback, called as GLFW calls it).
TEST(GlfwPointer, AKeyTappedBetweenFramesIsReadFromItsEvent) {
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display) GTEST_SKIP() << "no display (ctest runs this under xvfb-run)";
    if (!glfw_ready()) GTEST_SKIP() << "GLFW cannot start here";
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(320, 240, "ikebana key test", nullptr, nullptr);
    ASSERT_NE(window, nullptr);
    {
        GlfwPointerSource pointer(window);
        const GLFWkeyfun installed = glfwSetKeyCallback(window, nullptr);
        ASSERT_NE(installed, nullptr) << "the reader listens to no key events";
        glfwSetKeyCallback(window, installed);
        installed(window, GLFW_KEY_C, 0, GLFW_PRESS, 0);
        installed(window, GLFW_KEY_C, 0, GLFW_RELEASE, 0);
        installed(window, GLFW_KEY_ENTER, 0, GLFW_PRESS, 0);
        installed(window, GLFW_KEY_ENTER, 0, GLFW_REPEAT, 0);
        const auto first = pointer.read();
        EXPECT_TRUE(first.letter('C'));
        EXPECT_TRUE(first.finish_key);
        EXPECT_FALSE(first.letter('G'));
        const auto second = pointer.read();
        EXPECT_FALSE(second.letter('C')) << "one tap, one reading";
        EXPECT_TRUE(second.finish_key) << "Enter is still held";
        installed(window, GLFW_KEY_ENTER, 0, GLFW_RELEASE, 0);
        EXPECT_FALSE(pointer.read().finish_key);
    }
    glfwDestroyWindow(window);
}

// A trainee's click to let go of a stem held over the panel did nothing: quicker than a frame, the
// button was up at both readings. A click between two readings is one reading down, then one up.
TEST(GlfwPointer, AClickBetweenFramesIsReadFromItsEvents) {
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display) GTEST_SKIP() << "no display (ctest runs this under xvfb-run)";
    if (!glfw_ready()) GTEST_SKIP() << "GLFW cannot start here";
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(320, 240, "ikebana click test", nullptr, nullptr);
    ASSERT_NE(window, nullptr);
    {
        GlfwPointerSource pointer(window);
        const GLFWmousebuttonfun installed = glfwSetMouseButtonCallback(window, nullptr);
        ASSERT_NE(installed, nullptr) << "the reader listens to no button events";
        glfwSetMouseButtonCallback(window, installed);
        EXPECT_FALSE(pointer.read().grab_button);
        installed(window, GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
        installed(window, GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
        EXPECT_TRUE(pointer.read().grab_button) << "the click, down";
        EXPECT_FALSE(pointer.read().grab_button) << "and up";
        installed(window, GLFW_MOUSE_BUTTON_RIGHT, GLFW_PRESS, 0);
        EXPECT_FALSE(pointer.read().grab_button) << "the right button is not the grab";
        installed(window, GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
        EXPECT_TRUE(pointer.read().grab_button);
        EXPECT_TRUE(pointer.read().grab_button) << "held, it stays down";
        installed(window, GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
        EXPECT_FALSE(pointer.read().grab_button);
    }
    glfwDestroyWindow(window);
}
