#include "game/app/preview_window.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <thread>

#include <GLFW/glfw3.h>

#include "engine/assets/files.hpp"
#include "engine/render/png_image.hpp"
#include "game/app/window_stack.hpp"
#include "systems/presentation/draw_list.hpp"

namespace ikebana::game {

namespace {

constexpr double pi = 3.14159265358979323846;
const char* const who = "ikebana species preview: ";

} // namespace

render::StereoRig preview_framing(const components::FrameSnapshot& frame, double aspect, double yaw_rad) {
    glm::dvec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
    for (const auto& f : frame.flowers) {
        for (const auto& p : f.points_m) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    }
    if (!(lo.x <= hi.x)) lo = hi = glm::dvec3{0.0, 0.0, 0.1};
    const double around = 0.05; // a head's and its petals' reach beyond the stem's points
    lo -= glm::dvec3{around};
    hi += glm::dvec3{around};
    lo.z = std::min(lo.z, 0.0); // the kenzan, or the table under the flower, in the picture
    hi.z += 0.03;               // room for the caption over the top of the picture
    render::StereoRig rig;
    rig.aspect = aspect;
    rig.target_m = 0.5 * (lo + hi);
    const glm::dvec3 size = hi - lo;
    const double half_fov = 0.5 * rig.vertical_fov_rad;
    const double across = std::max(size.x, size.y);
    const double distance = 1.1 * std::max(0.5 * size.z / std::tan(half_fov), 0.5 * across / (std::tan(half_fov) * aspect)) + 0.5 * across;
    const double lift = 10.0 * pi / 180.0;
    rig.position_m = rig.target_m + distance * glm::dvec3{std::sin(yaw_rad) * std::cos(lift), -std::cos(yaw_rad) * std::cos(lift), std::sin(lift)};
    rig.near_m = 0.01;
    rig.far_m = 10.0 * distance;
    return rig;
}

int run_preview_window(const PreviewWindowOptions& o, const std::function<Result<std::vector<PreviewView>>()>& measure) {
    auto views = measure();
    if (!views) {
        std::cerr << who << views.error().message << "\n";
        return 2;
    }
    if (views->empty()) return 2;
    auto window = platform::Window::create("Ikebana: species preview", o.width, o.height);
    if (!window) {
        std::cerr << who << window.error().message << "; without --window the preview is written as pictures (--out)\n";
        return 3;
    }
    auto stack =
        WindowStack::open(std::move(window).value(), {.width = o.width, .height = o.height, .mode = render::StereoMode::mono, .validation = o.validation, .need_ui = false, .msaa = 0});
    if (!stack) {
        std::cerr << who << stack.error().message << "\n";
        return 3;
    }
    WindowStack& s = **stack;
    std::size_t view = 0;
    double yaw = 0.0;
    bool dragging = false;
    double drag_x = 0.0;
    std::vector<bool> held(views->size(), false);
    std::string problem; // the last save that did not load, said over the last good preview
    auto seen = assets::last_changed(o.file);
    auto last_check = std::chrono::steady_clock::now();
    auto last_frame = last_check;
    std::uint32_t presented = 0, measured = 1, after_last = 0;
    const bool counting_passes = o.watch && o.passes > 0;
    while (!s.window().should_close()) {
        s.window().poll_events();
        if (s.window().key_down(GLFW_KEY_ESCAPE)) s.window().request_close();
        for (std::size_t k = 0; k < views->size() && k < 9; ++k) {
            const bool down = s.window().key_down(GLFW_KEY_1 + static_cast<int>(k));
            if (down && !held[k]) {
                view = k;
                yaw = 0.0;
            }
            held[k] = down;
        }
        const auto now = std::chrono::steady_clock::now();
        const double dt = std::min(0.1, std::chrono::duration<double>(now - last_frame).count());
        last_frame = now;
        // Drag to turn; the turntable turns by itself, once in 12 s, while it is not held.
        const bool button = s.window().mouse_down(GLFW_MOUSE_BUTTON_LEFT);
        const double x = s.window().cursor().first;
        if (button && dragging) yaw += 0.01 * (x - drag_x);
        dragging = button;
        drag_x = x;
        if ((*views)[view].turning && !dragging) yaw += dt * 2.0 * pi / 12.0;

        if (o.watch && now - last_check > std::chrono::milliseconds(250)) {
            last_check = now;
            if (const auto t = assets::last_changed(o.file); t != seen) {
                std::this_thread::sleep_for(std::chrono::milliseconds(150)); // a save is often a truncate and a write
                seen = assets::last_changed(o.file);
                ++measured;
                auto again = measure();
                if (again && !again->empty()) {
                    views = std::move(again);
                    held.assign(views->size(), false);
                    view = std::min(view, views->size() - 1);
                    problem.clear();
                    std::printf("%s changed: measured and shown again\n", o.file.c_str());
                } else {
                    problem = again ? "no trials" : again.error().message;
                    std::cerr << who << problem << "\n";
                }
                std::fflush(stdout);
            }
        }

        const auto& v = (*views)[view];
        std::vector<std::string> lines = v.caption;
        std::string keys;
        for (const auto& each : *views) keys += (keys.empty() ? "keys: " : ", ") + each.key + " " + each.title;
        lines.push_back(keys);
        lines.push_back("drag to turn, Esc closes" + std::string(o.watch ? "; a save shows it again" : ""));
        const auto extent = s.window().framebuffer();
        const double aspect = extent.height > 0 ? static_cast<double>(extent.width) / static_cast<double>(extent.height) : 0.75;
        std::vector<render::OverlayPanel> panels;
        render::OverlayPanel caption;
        caption.scale = std::clamp(static_cast<float>(extent.width) / 330.0f, 1.0f, 1.5f); // a narrow window's lines stay whole
        caption.lines = std::move(lines);
        panels.push_back(std::move(caption));
        if (!problem.empty()) {
            render::OverlayPanel bad;
            bad.scale = panels.front().scale;
            bad.origin_px = {12.0f, static_cast<float>(extent.height) - 60.0f};
            bad.panel_colour = {0.6f, 0.05f, 0.05f, 0.85f};
            bad.lines = {"the last save does not load (this is the one before):", problem.substr(0, 90)};
            panels.push_back(std::move(bad));
        }
        s.renderer().set_overlay(std::move(panels));
        const bool finishing = counting_passes && measured >= o.passes;
        const bool last = (o.frames > 0 && presented + 1 >= o.frames) || (finishing && after_last + 1 >= 10);
        auto frame = s.present(systems::build_draw_list(v.frame), preview_framing(v.frame, aspect, yaw), last && !o.screenshot.empty());
        if (!frame) {
            std::cerr << who << frame.error().message << "\n";
            return 3;
        }
        if (!*frame) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20)); // minimised
            continue;
        }
        if ((*frame)->presented) {
            ++presented;
            if (finishing) ++after_last;
        }
        if ((*frame)->screenshot) {
            if (auto written = render::write_png(o.screenshot, *(*frame)->screenshot); !written) std::cerr << who << written.error().message << "\n";
            else std::printf("screenshot in %s\n", o.screenshot.c_str());
        }
        if (last) break;
    }
    vkDeviceWaitIdle(s.vulkan().device());
    return 0;
}

} // namespace ikebana::game
