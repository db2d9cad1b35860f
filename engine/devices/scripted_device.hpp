#pragma once
// Devices that play back a file: a scripted trajectory (timed poses and buttons, linearly interpolated;
// tests, demos, CI) and the replay of a recorded session (every sample exactly as recorded, no
// interpolation). Both read the same CSV:
//
//   # comment lines start with '#'
//   time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons
//   0.000,0.00,0.00,0.10,0,0,0,0
//   0.500,0.02,0.00,0.05,0,0,0,1
//
// Times strictly increase; buttons is a bitmask (bit 0: grab). DeviceRecorder writes this format with
// full double precision, so a replay reproduces every sample bit for bit.
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "engine/assets/files.hpp"
#include "engine/core/async_line_writer.hpp"
#include "engine/core/result.hpp"
#include "engine/devices/haptic_device.hpp"

namespace ikebana::devices {

struct Keyframe {
    double time_s;
    glm::dvec3 position_m;
    glm::dvec3 rotation_rad;
    std::uint32_t buttons;
};

// What a trajectory may hold: positions within 10 m (no device reaches further; 1e15 m once hung the
// collision grid), rotations within 1000 rad, times within 1e9 s (the microsecond timeline's reach
// with room to spare).
inline constexpr double max_trajectory_reach_m = 10.0;
inline constexpr double max_trajectory_rotation_rad = 1000.0;
inline constexpr double max_trajectory_time_s = 1e9;

// Errors name the file, line and column.
Result<std::vector<Keyframe>> parse_trajectory(std::string_view text, const std::string& label);
// `max_bytes`: a recorded session's hand files may be larger than a hand-written trajectory (a noisy
// position device changes at every 1 kHz tick: about 160 kB a second).
Result<std::vector<Keyframe>> load_trajectory(const std::filesystem::path& path, std::uintmax_t max_bytes = assets::max_text_file_bytes);

class ScriptedDevice final : public HapticDevice {
public:
    enum class Mode { interpolate, replay };
    ScriptedDevice(std::vector<Keyframe> keys, Mode mode, std::string name = "scripted");
    [[nodiscard]] const DeviceCapabilities& capabilities() const override { return caps_; }
    Result<DeviceSample> poll(std::int64_t now_us) override;
    // Forces are not applied to anything; the last one is kept for tests to inspect.
    Result<void> send_force(glm::dvec3 force_n) override;
    [[nodiscard]] glm::dvec3 last_force() const noexcept { return last_force_; }
    [[nodiscard]] double duration_s() const noexcept { return keys_.empty() ? 0.0 : keys_.back().time_s; }
    // Replays a rate device's recording (a SpaceMouse's pushes, which the hand integrates into motion).
    void report_pushes() noexcept { caps_.reports_position = false; }
    // Replays a device that went away: its reads fail in each [from, to) microsecond span.
    void away(std::vector<std::pair<std::int64_t, std::int64_t>> spans) { away_ = std::move(spans); }

private:
    std::vector<Keyframe> keys_;
    std::vector<std::pair<std::int64_t, std::int64_t>> away_;
    Mode mode_;
    DeviceCapabilities caps_;
    glm::dvec3 last_force_{0.0};
};

// Writes the samples a device produced, with their times, in the trajectory format: each one that
// differs from the last written (a mouse's hand stands still most of the time). Replayed in
// ScriptedDevice's replay mode, which holds each sample until the next, every tick reads what it read.
// record() runs on the 1 kHz thread: it formats the line and hands it to an AsyncLineWriter, whose
// own thread writes it and flushes every 100 ms (a recording cut short by a crash keeps all but its
// last moments). `when_full`: drop (and count) in real time, wait in a headless run.
class DeviceRecorder {
public:
    explicit DeviceRecorder(std::ostream& out, AsyncLineWriter::WhenFull when_full);
    void record(const DeviceSample& sample);
    // Everything recorded so far is in the stream (not for the 1 kHz thread).
    void flush() { writer_.flush(); }
    // Samples lost because the writer fell seconds behind (real time only): a replay of this recording
    // would part from the session.
    [[nodiscard]] std::uint64_t dropped() const noexcept { return writer_.dropped(); }
    // The file refused a write (a full disk): the recording is not whole (AsyncLineWriter::failed).
    [[nodiscard]] bool failed() const noexcept { return writer_.failed(); }
    [[nodiscard]] std::string failure() const { return writer_.failure(); }
    void on_failure(std::function<void(const std::string&)> tell) { writer_.on_failure(std::move(tell)); }

private:
    AsyncLineWriter writer_;
    bool wrote_ = false;
    DeviceSample last_;
};

} // namespace ikebana::devices
