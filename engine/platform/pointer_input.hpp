#pragma once
// The mouse and keyboard as the window sees them, read once per tick. The GLFW reader is the only
// part that needs a window; everything that turns it into hands takes a PointerSource.
#include <cstdint>

#include <glm/glm.hpp>

#include "engine/sched/triple_buffer.hpp"

struct GLFWwindow;

namespace ikebana::platform {

// A line from the viewer's eye through the cursor, in the hands' device space, from whoever knows the
// camera (the trainee window). With it the hand moves as the point under the cursor moves at the
// hand's depth, so a hand put under the cursor stays under it.
struct PointerRay {
    glm::dvec3 origin_m{0.0};
    glm::dvec3 direction{0.0};
    int eye = 0;        // whose image the cursor is in (-1 left, 1 right, 0 one image for both)
    bool valid = false; // none: the hands follow the cursor's motion with the Config's scales
};

struct PointerState {
    glm::dvec2 cursor_px{0.0};
    glm::dvec2 window_px{1.0, 1.0};
    bool grab_button = false;   // left mouse button
    bool depth_modifier = false; // Shift: vertical mouse motion moves the hand in depth
    bool switch_hand = false;   // Tab is down
    double scroll = 0.0;        // accumulated wheel clicks (depth)
    // The view, not the hands: the right button drags the camera round, the arrows turn it, Enter ends
    // the training. Read with the rest so that a scripted pointer can drive a whole session.
    bool orbit_button = false;  // right mouse button
    glm::dvec2 arrows{0.0};     // x: right minus left, y: up minus down (each -1, 0 or 1), as held now
    // The arrows' presses, counted (a held key's auto-repeats too), accumulated like the wheel: x right
    // minus left, y up minus down. Without Ctrl (arrow_presses) they step the camera round the table;
    // with Ctrl (tilt_presses) they tilt the held stem a step at a time.
    glm::dvec2 arrow_presses{0.0};
    glm::dvec2 tilt_presses{0.0};
    // The camera's turn about the vertical as the window draws it: the mouse's hands stay where they
    // are in the room when it turns (MouseKeyboardHands), holding what they hold as they held it.
    double view_yaw_rad = 0.0;
    // The window asks the active hand to go to a place (device space) at once, counted: a press on a
    // stem lying on the table far from its bottom end takes it by that end (the hand goes there).
    std::uint32_t hand_moves = 0;
    glm::dvec3 hand_to_m{0.0};
    // Where the active hand's held stem is held fast (device space), when it is (turn_about set): a
    // tilt then turns it about there, the hand going round that point, not about the grip (turned
    // about the grip, a stem in a kenzan's pins was levered out of them by Ctrl+arrows).
    bool turn_about = false;
    glm::dvec3 turn_about_m{0.0};
    // Which way the active hand's held stem points, bottom to tip (device space, unit), when it holds
    // one (lean_along set): a lean (Ctrl+drag, Ctrl+arrows, the panel's buttons) then moves its tip the
    // way the drag or arrow goes, as seen, by the same degrees whatever way it points (turned about
    // fixed axes, a stem lying flat to the right only rolled when leant toward the viewer).
    bool lean_along = false;
    glm::dvec3 lean_along_dir{0.0, 0.0, 1.0};
    bool finish_key = false;    // Enter
    bool quit_key = false;      // Escape
    // Ctrl held: what the game makes of mouse motion then is its own (a lesson tilts the held stem).
    bool tilt_modifier = false;  // Ctrl
    // The letter keys, each read from its events like Enter (bit i: 'A' + i). What a letter does is
    // the game's (a lesson's C cuts, G shows the form, R starts again): the engine only reads keys.
    std::uint32_t letters = 0;
    [[nodiscard]] bool letter(char c) const noexcept { return c >= 'A' && c <= 'Z' && (letters >> (c - 'A') & 1u) != 0; }
    void set_letter(char c, bool down) noexcept {
        if (c < 'A' || c > 'Z') return;
        const std::uint32_t bit = 1u << (c - 'A');
        letters = down ? letters | bit : letters & ~bit;
    }
    // Set when the reader put the cursor back in the window's middle this reading: where it was then
    // (the motion up to there still counts); negative when it was not moved.
    glm::dvec2 warped_from_px{-1.0, -1.0};
    // Through the cursor now, and through where it was at the reader's last reading (both through this
    // reading's camera, so turning the camera alone moves no hand).
    PointerRay ray;
    PointerRay ray_before;
};

// A key's presses as events, reported as readings: each press gives one reading with the key down
// after one with it up, however short the tap and however many taps came between two readings (two
// taps of C in one frame are two cuts). Between presses the reading follows the key as it is.
class KeyTaps {
public:
    void press() noexcept {
        down_ = true;
        ++pending_;
    }
    void release() noexcept { down_ = false; }
    // Presses not yet read are dropped; a key held down stays down.
    void forget() noexcept {
        pending_ = 0;
        reported_down_ = down_;
    }
    [[nodiscard]] bool report() noexcept {
        if (pending_ > 0) {
            if (reported_down_) {
                reported_down_ = false; // the next press needs an edge: up first
            } else {
                reported_down_ = true;
                --pending_;
            }
            return reported_down_;
        }
        reported_down_ = down_;
        return reported_down_;
    }

private:
    bool down_ = false;
    bool reported_down_ = false;
    unsigned pending_ = 0;
};

class PointerSource {
public:
    virtual ~PointerSource() = default;
    [[nodiscard]] virtual PointerState read() = 0;
};

// Reads a GLFW window: the cursor as it is, the scroll wheel accumulated, and the left button and the
// keys that act when pressed (Enter, Esc, Tab, the letters A-Z) from GLFW's events, so no tap or click
// is lost between two frames. Held keys (Ctrl, Shift, the arrows) are read as they are.
class GlfwPointerSource final : public PointerSource {
public:
    explicit GlfwPointerSource(GLFWwindow* window);
    // Lessons reach further than the window is wide: the cursor is put back in the middle at the edges.
    void recentre_at_edges(bool on) noexcept { recentre_at_edges_ = on; }
    // Moves the cursor (window pixels): onto the hand it drives, when the hand has gone elsewhere.
    void put_cursor(glm::dvec2 px);
    // Drops the key presses not yet read (letters typed into a text field are no cuts).
    void forget_taps() noexcept {
        for (auto& t : taps_) t = KeyTaps{};
        for (auto& t : letter_taps_) t = KeyTaps{};
        button_taps_.forget();
    }
    ~GlfwPointerSource() override;
    GlfwPointerSource(const GlfwPointerSource&) = delete;
    GlfwPointerSource& operator=(const GlfwPointerSource&) = delete;
    [[nodiscard]] PointerState read() override;

    // The keys read from events; an index into taps_.
    enum Tap : int { enter, escape, tab, tap_count };

private:
    void on_key(int key, int action, int mods);
    GLFWwindow* window_;
    double scroll_ = 0.0;
    glm::dvec2 arrow_presses_{0.0}, tilt_presses_{0.0};
    KeyTaps taps_[tap_count];
    KeyTaps letter_taps_[26]; // A to Z
    KeyTaps button_taps_;     // the left mouse button
    bool recentre_at_edges_ = false;
};

// The pointer handed across threads: GLFW may only be read on the main thread, but the hands are read
// by the simulation's own 1 kHz thread. The main thread stores what it read each frame; the hands read
// the latest (the cursor moves in frame-sized steps, as it did when the window read it). Lock-free (a
// triple buffer): the SCHED_FIFO haptic thread must never wait on the main thread. One storing thread,
// one reading thread.
class SharedPointerSource final : public PointerSource {
public:
    void store(const PointerState& state);
    [[nodiscard]] PointerState read() override;

private:
    sched::TripleBuffer<PointerState> buffer_;
};

} // namespace ikebana::platform
