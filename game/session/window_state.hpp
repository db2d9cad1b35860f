#pragma once
// What the trainee window shows, as data for a script that works the window from outside: the app
// writes it each frame (`ikebana --state-out FILE`), a scripted mouse reads it as a person reads the
// screen. Plain values only: where the stems are, what each hand holds, when the window last read
// the mouse and keyboard (so that a script knows its motion has been seen), and the last result.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "components/snapshot.hpp"
#include "engine/core/result.hpp"
#include "game/render/pointer_aim.hpp"

namespace ikebana::game {

struct WindowState {
    std::uint64_t frame = 0;          // frames the window has read input for
    std::int64_t input_read_at_us = 0; // steady clock (CLOCK_MONOTONIC, shared by processes) when it read them
    std::int64_t sim_time_us = 0;     // the snapshot's simulated time
    glm::dvec2 window_px{0.0};
    glm::dvec2 cursor_px{0.0};
    // The hand the mouse drives, and how far the cursor moves for a metre of it there (sideways, up),
    // when the pointer is aimed through the camera (0, 0: it is not; the hands follow motion instead).
    std::uint8_t active_hand = 1;
    glm::dvec2 px_per_m{0.0};
    struct Hand {
        bool holding = false;
        std::int32_t held_flower = -1;
        glm::dvec3 position_m{0.0}; // its cube
        glm::dvec3 device_m{0.0};   // where its device puts it
        // The force the simulation asks for and the one its device got after the safety chain
        // (`pushes` false: a device that pushes nothing, the mouse), and the state of its link.
        glm::dvec3 force_asked_n{0.0};
        glm::dvec3 force_sent_n{0.0};
        bool pushes = false;
        std::string link = "answering";
    };
    Hand hands[2];
    struct Flower {
        std::string species;
        std::vector<glm::dvec3> points_m;
        double diameter_m = 0.0;
        bool in_kenzan = false;
        bool fallen = false;
        components::FallReason fall_reason = components::FallReason::none;
        double yield_holding_nm = 0.0, yield_gravity_nm = 0.0;
        std::uint32_t pins_engaged = 0;
        double depth_m = 0.0;
    };
    std::vector<Flower> flowers;
    std::optional<glm::dvec3> kenzan_origin_m;
    double kenzan_pin_height_m = 0.0;
    // Which screen is up ("start": the start screen, "lesson"), and its interface's buttons, where a
    // script finds them (window pixels, the left eye's copy in side by side).
    std::string screen = "lesson";
    // How the scene is shown: "mono" (a flat screen), "sbs", "anaglyph" or "rows" (render::StereoMode).
    std::string display;
    struct Button {
        std::string label;
        glm::dvec2 min_px{0.0}, max_px{0.0};
    };
    std::vector<Button> buttons;
    // Where things are on the screen this frame (window pixels; side by side, each eye's copy): every
    // panel of text or controls drawn, each eye's scene (the 3D view beside the panels), and in it the
    // box of the kenzan ("kenzan") and of each stem standing in it ("stem 3: willow"), cut to the scene.
    struct Box {
        std::string name;
        int eye = 0; // -1 left, 1 right, 0 the one image both share
        glm::dvec2 min_px{0.0}, size_px{0.0};
    };
    struct Layout {
        std::vector<Box> panels;
        std::vector<Box> views;
        std::vector<Box> scene;
    };
    Layout layout;
    std::uint64_t results = 0;  // results shown so far (Enter)
    std::string result_json;    // the last one, as `lesson score --json` writes it (empty: none yet)
};

// The first panel that covers part of a scene box or of an eye's view, in words ("'session' covers
// 'stem 2: willow' (left eye) by 40x12 px"); nothing when none does.
[[nodiscard]] std::optional<std::string> panel_over_scene(const WindowState& state);

// Fills the layout's views and scene boxes for the frame as the window draws it (`panels` are the
// interface's, in one eye's area: side by side, each is put in both halves).
void take_layout(WindowState& state, const PointerView& view, glm::dvec2 window_px, const components::FrameSnapshot& frame,
                 const std::vector<WindowState::Box>& panels);

// Fills the state's picture of the world from a frame snapshot.
void take_snapshot(WindowState& state, const components::FrameSnapshot& frame);
[[nodiscard]] std::string window_state_json(const WindowState& state);
// Errors name the field; a reader retries on a file caught mid-replace (the writer renames, so it is not).
Result<WindowState> parse_window_state(std::string_view text, const std::string& label);
// Writes the file whole (a temporary beside it, then renamed): a reader never sees half of it.
Result<void> write_window_state(const std::string& path, const WindowState& state);

} // namespace ikebana::game
