#include "engine/platform/pointer_input.hpp"

#include <GLFW/glfw3.h>

namespace ikebana::platform {

GlfwPointerSource::GlfwPointerSource(GLFWwindow* window) : window_(window) {
    // A key tapped between two frames' readings still counts once (C, G, R, Enter are taps).
    glfwSetInputMode(window, GLFW_STICKY_KEYS, GLFW_TRUE);
    glfwSetWindowUserPointer(window_, this);
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double y) {
        if (auto* self = static_cast<GlfwPointerSource*>(glfwGetWindowUserPointer(w))) self->scroll_ += y;
    });
}

GlfwPointerSource::~GlfwPointerSource() {
    glfwSetScrollCallback(window_, nullptr);
    glfwSetWindowUserPointer(window_, nullptr);
}

PointerState GlfwPointerSource::read() {
    PointerState s;
    glfwGetCursorPos(window_, &s.cursor_px.x, &s.cursor_px.y);
    int width = 1;
    int height = 1;
    glfwGetWindowSize(window_, &width, &height);
    s.window_px = {width > 0 ? width : 1, height > 0 ? height : 1};
    s.grab_button = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    s.depth_modifier = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    s.switch_hand = glfwGetKey(window_, GLFW_KEY_TAB) == GLFW_PRESS;
    s.scroll = scroll_;
    auto key = [&](int k) { return glfwGetKey(window_, k) == GLFW_PRESS ? 1.0 : 0.0; };
    s.orbit_button = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    s.arrows = {key(GLFW_KEY_RIGHT) - key(GLFW_KEY_LEFT), key(GLFW_KEY_UP) - key(GLFW_KEY_DOWN)};
    s.finish_key = key(GLFW_KEY_ENTER) > 0.0 || key(GLFW_KEY_KP_ENTER) > 0.0;
    s.quit_key = key(GLFW_KEY_ESCAPE) > 0.0;
    s.tilt_modifier = key(GLFW_KEY_LEFT_CONTROL) > 0.0 || key(GLFW_KEY_RIGHT_CONTROL) > 0.0;
    s.cut_key = key(GLFW_KEY_C) > 0.0;
    s.ghost_key = key(GLFW_KEY_G) > 0.0;
    s.reset_key = key(GLFW_KEY_R) > 0.0;
    // The hands follow the cursor's motion, and a cursor stops at the window's edge: one that reaches
    // it (a hand carried far to a side, a long Ctrl+drag) is put back in the middle, its motion up to
    // the edge still counted (the hand does not jump, and it can go on).
    const double margin = 24.0;
    const bool inside = s.cursor_px.x >= 0.0 && s.cursor_px.y >= 0.0 && s.cursor_px.x <= s.window_px.x && s.cursor_px.y <= s.window_px.y;
    const bool at_edge = s.cursor_px.x < margin || s.cursor_px.y < margin || s.cursor_px.x > s.window_px.x - margin || s.cursor_px.y > s.window_px.y - margin;
    if (recentre_at_edges_ && inside && at_edge && s.window_px.x > 4 * margin && s.window_px.y > 4 * margin &&
        glfwGetWindowAttrib(window_, GLFW_FOCUSED) == GLFW_TRUE) {
        s.warped_from_px = s.cursor_px;
        s.cursor_px = 0.5 * s.window_px;
        glfwSetCursorPos(window_, s.cursor_px.x, s.cursor_px.y);
    }
    return s;
}

void GlfwPointerSource::put_cursor(glm::dvec2 px) { glfwSetCursorPos(window_, px.x, px.y); }

void SharedPointerSource::store(const PointerState& state) {
    buffer_.write_buffer() = state;
    buffer_.publish();
}

PointerState SharedPointerSource::read() {
    buffer_.update();
    return buffer_.read_buffer();
}

} // namespace ikebana::platform
