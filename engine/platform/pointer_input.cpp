#include "engine/platform/pointer_input.hpp"

#include <GLFW/glfw3.h>

namespace ikebana::platform {

GlfwPointerSource::GlfwPointerSource(GLFWwindow* window) : window_(window) {
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
        if (auto* self = static_cast<GlfwPointerSource*>(glfwGetWindowUserPointer(w))) self->on_key(key, action, mods);
    });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double y) {
        if (auto* self = static_cast<GlfwPointerSource*>(glfwGetWindowUserPointer(w))) self->scroll_ += y;
    });
    // The left button from its events too: a click quicker than a frame (a trainee's click to let go of
    // a stem held over the panel) is a reading down and one up, not nothing.
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int) {
        auto* self = static_cast<GlfwPointerSource*>(glfwGetWindowUserPointer(w));
        if (!self || button != GLFW_MOUSE_BUTTON_LEFT) return;
        if (action == GLFW_PRESS) self->button_taps_.press();
        else if (action == GLFW_RELEASE) self->button_taps_.release();
    });
    if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) button_taps_.press(); // held as it opened
}

GlfwPointerSource::~GlfwPointerSource() {
    glfwSetMouseButtonCallback(window_, nullptr);
    glfwSetScrollCallback(window_, nullptr);
    glfwSetKeyCallback(window_, nullptr);
    glfwSetWindowUserPointer(window_, nullptr);
}

void GlfwPointerSource::on_key(int key, int action, int mods) {
    if (key == GLFW_KEY_LEFT || key == GLFW_KEY_RIGHT || key == GLFW_KEY_UP || key == GLFW_KEY_DOWN) {
        // Each press is a step, and so is each repeat of a held key: eight Left then eight Right come
        // back to where they started, however long each was held down.
        if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
        const glm::dvec2 step = key == GLFW_KEY_LEFT ? glm::dvec2{-1, 0} : key == GLFW_KEY_RIGHT ? glm::dvec2{1, 0} : key == GLFW_KEY_UP ? glm::dvec2{0, 1} : glm::dvec2{0, -1};
        ((mods & GLFW_MOD_CONTROL) != 0 ? tilt_presses_ : arrow_presses_) += step;
        return;
    }
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) {
        KeyTaps& letter = letter_taps_[key - GLFW_KEY_A];
        if (action == GLFW_PRESS) letter.press();
        else if (action == GLFW_RELEASE) letter.release();
        return;
    }
    int tap = -1;
    switch (key) {
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER: tap = enter; break;
    case GLFW_KEY_ESCAPE: tap = escape; break;
    case GLFW_KEY_TAB: tap = tab; break;
    default: return;
    }
    if (action == GLFW_PRESS) taps_[tap].press();
    else if (action == GLFW_RELEASE) taps_[tap].release();
    // GLFW_REPEAT: a held key is one press.
}

PointerState GlfwPointerSource::read() {
    PointerState s;
    glfwGetCursorPos(window_, &s.cursor_px.x, &s.cursor_px.y);
    int width = 1;
    int height = 1;
    glfwGetWindowSize(window_, &width, &height);
    s.window_px = {width > 0 ? width : 1, height > 0 ? height : 1};
    s.grab_button = button_taps_.report();
    s.depth_modifier = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    s.switch_hand = taps_[tab].report();
    s.scroll = scroll_;
    s.arrow_presses = arrow_presses_;
    s.tilt_presses = tilt_presses_;
    auto key = [&](int k) { return glfwGetKey(window_, k) == GLFW_PRESS ? 1.0 : 0.0; };
    s.orbit_button = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    s.arrows = {key(GLFW_KEY_RIGHT) - key(GLFW_KEY_LEFT), key(GLFW_KEY_UP) - key(GLFW_KEY_DOWN)};
    s.finish_key = taps_[enter].report();
    s.quit_key = taps_[escape].report();
    s.tilt_modifier = key(GLFW_KEY_LEFT_CONTROL) > 0.0 || key(GLFW_KEY_RIGHT_CONTROL) > 0.0;
    for (int i = 0; i < 26; ++i) s.set_letter(static_cast<char>('A' + i), letter_taps_[i].report());
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
