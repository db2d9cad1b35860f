#include <gtest/gtest.h>

#include <cstdlib>

#include <GLFW/glfw3.h>

#include "engine/platform/pointer_input.hpp"

using namespace ikebana::platform;

// A real window (under Xvfb in CI; skipped where there is no display).
TEST(GlfwPointer, ReadsTheCursorOfARealWindow) {
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display) GTEST_SKIP() << "no display (ctest runs this under xvfb-run)";
    if (glfwInit() != GLFW_TRUE) GTEST_SKIP() << "GLFW cannot start here";
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
    glfwTerminate();
}
