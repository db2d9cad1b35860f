#pragma once
// The mouse and keyboard as the window sees them, read once per tick. The GLFW reader is the only
// part that needs a window; everything that turns it into hands takes a PointerSource.
#include <cstdint>

#include <glm/glm.hpp>

struct GLFWwindow;

namespace ikebana::platform {

struct PointerState {
    glm::dvec2 cursor_px{0.0};
    glm::dvec2 window_px{1.0, 1.0};
    bool grab_button = false;   // left mouse button
    bool depth_modifier = false; // Shift: vertical mouse motion moves the hand in depth
    bool switch_hand = false;   // Tab is down
    double scroll = 0.0;        // accumulated wheel clicks (depth)
};

class PointerSource {
public:
    virtual ~PointerSource() = default;
    [[nodiscard]] virtual PointerState read() = 0;
};

// Polls a GLFW window (cursor, buttons, keys) and accumulates its scroll wheel.
class GlfwPointerSource final : public PointerSource {
public:
    explicit GlfwPointerSource(GLFWwindow* window);
    ~GlfwPointerSource() override;
    GlfwPointerSource(const GlfwPointerSource&) = delete;
    GlfwPointerSource& operator=(const GlfwPointerSource&) = delete;
    [[nodiscard]] PointerState read() override;

private:
    GLFWwindow* window_;
    double scroll_ = 0.0;
};

} // namespace ikebana::platform
