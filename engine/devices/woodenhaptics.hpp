#pragma once
// WoodenHaptics (KTH's open-hardware 3-DoF force-feedback device) over its 2017 raw-HID firmware.
// The device sends encoder counts and takes motor currents; all kinematics are on the host, as in the
// CHAI3D fork's cWoodenDevice it was written for. Everything that turns bytes into metres and
// newtons into milliamps is a pure function here, so it is tested without the hardware
// (docs/haptics.md, "WoodenHaptics over raw HID").
//
// Frames. The kinematic functions work in the WoodenHaptics (CHAI3D) frame the published code uses:
// x towards the operator, y to the operator's right, z up, origin at the workspace centre. The
// device class turns that into this project's device frame (x right, y away from the user, z up, as
// the DIY device reports): device = (wh.y, -wh.x, wh.z).
#include <array>
#include <limits>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <glm/glm.hpp>

#include "engine/core/pi_mutex.hpp"
#include "engine/core/result.hpp"
#include "engine/devices/haptic_device.hpp"
#include "engine/devices/hid_transport.hpp"

namespace ikebana::devices {

// The USB ids the 2017 firmware enumerates with (the host code opens exactly these).
inline constexpr std::uint16_t woodenhaptics_vendor_id = 0x1234;
inline constexpr std::uint16_t woodenhaptics_product_id = 0x0006;

// Device -> host: four int16, little-endian: encoder counts a, b, c and a spare word.
inline constexpr std::size_t woodenhaptics_input_size = 8;
// Host -> device: report id 0, then four int16, little-endian: motor currents a, b, c in mA and a
// spare word (sent as 0).
inline constexpr std::size_t woodenhaptics_output_size = 9;
// What the firmware's current loop is set up for (ESCON drivers scaled so that 90 % PWM = 3 A);
// the host never asks for more.
inline constexpr double woodenhaptics_max_current_mA = 3000.0;

// Which way a positive current turns each motor, relative to its encoder's positive count. On the
// 2017 board encoder a counts against motor a (the published code negates count a but not current a);
// b and c agree with their encoders.
inline constexpr std::array<double, 3> woodenhaptics_current_direction{-1.0, 1.0, 1.0};

using WoodenHapticsCounts = std::array<std::int16_t, 4>; // a, b, c, spare

// Every geometric and electrical parameter, SI units. Defaults are the published design's
// (default_woody() in the CHAI3D fork's CWoodenDevice.cpp); assets/devices/woodenhaptics.json ships
// them and a builder's own file can replace them.
struct WoodenHapticsProfile {
    std::string name = "WoodenHaptics (KTH, 2017 raw-HID firmware)";
    // Body a is the base that turns about z; its length is the height of the shoulder joint above
    // the table. Body b is the upper arm (from the shoulder), body c the forearm (to the handle).
    double length_body_a_m = 0.080;
    double length_body_b_m = 0.205;
    double length_body_c_m = 0.245;
    // Each joint is driven through a cable from a small capstan on the motor shaft to a large drum on
    // the body: the joint turns drum/capstan times slower than the motor and with that much more torque.
    std::array<double, 3> capstan_diameter_m{0.010, 0.010, 0.010};
    std::array<double, 3> drum_diameter_m{0.160, 0.120, 0.120};
    // Where the workspace centre is in the base frame; positions are reported relative to it.
    glm::dvec3 workspace_origin_m{0.220, 0.0, 0.080};
    double workspace_radius_m = 0.100;
    std::array<double, 3> torque_constant_nm_per_a{0.0259, 0.0259, 0.0259};
    // Quadrature counts per motor revolution (500-line encoders, counted on both edges of both channels).
    std::array<double, 3> encoder_counts_per_rev{2000.0, 2000.0, 2000.0};
    // What the device renders well: the largest force, and the stiffness and damping a virtual
    // coupling should stay under to keep it stable.
    double max_force_n = 5.0;
    double max_stiffness_n_per_m = 1000.0;
    double max_damping_ns_per_m = 8.0;
    // The 2017 firmware streams its encoders at about 1 kHz: 20 ms without one is a hung device.
    double silent_after_ms = 20.0;
};

// Reads a profile through JsonChecker: every field present and in range, unknown keys refused, each
// problem named as `file: /field: expected ..., got ...`.
Result<WoodenHapticsProfile> parse_woodenhaptics_profile(std::string_view text, const std::string& label);
Result<WoodenHapticsProfile> load_woodenhaptics_profile(const std::filesystem::path& path);

// nullopt unless `bytes` is exactly one 8-byte input report.
[[nodiscard]] std::optional<WoodenHapticsCounts> decode_woodenhaptics_report(std::span<const std::uint8_t> bytes);
// Report id 0 and the three currents, rounded to whole mA, clamped to +-3000, non-finite as 0.
[[nodiscard]] std::array<std::uint8_t, woodenhaptics_output_size> encode_woodenhaptics_currents(std::array<double, 3> current_mA);

// Joint angles (radians) from encoder counts:
//   theta_a  the base's turn about z (0: the arm points along +x, towards the operator)
//   theta_b  the upper arm's tilt from vertical (0: straight up, positive: leaning towards +x)
//   theta_c  the forearm's angle from straight down (pi/2: horizontal, pointing away from the base)
// Counts are relative to power-up, so the device starts in its home pose: upper arm up, forearm
// level, both pointing along +x (theta = 0, 0, pi/2).
[[nodiscard]] glm::dvec3 woodenhaptics_angles(const WoodenHapticsProfile& profile, const WoodenHapticsCounts& counts);
// Handle position (metres, WoodenHaptics frame, relative to the workspace origin).
[[nodiscard]] glm::dvec3 woodenhaptics_position(const WoodenHapticsProfile& profile, glm::dvec3 angles);
// d position / d angles; column j is the handle's velocity per unit rate of joint j.
[[nodiscard]] glm::dmat3 woodenhaptics_jacobian(const WoodenHapticsProfile& profile, glm::dvec3 angles);
// Joint torques (N m) that put `force_n` (WoodenHaptics frame) on the handle: J^T F.
[[nodiscard]] glm::dvec3 woodenhaptics_joint_torques(const WoodenHapticsProfile& profile, glm::dvec3 angles, glm::dvec3 force_n);
// Motor currents (mA, unclamped) for `force_n`: joint torques through the capstan reductions to the
// motors, divided by the torque constants, signed as the board drives them.
[[nodiscard]] std::array<double, 3> woodenhaptics_currents(const WoodenHapticsProfile& profile, glm::dvec3 angles, glm::dvec3 force_n);

// Between the WoodenHaptics frame and this project's device frame (a quarter turn about z).
[[nodiscard]] constexpr glm::dvec3 woodenhaptics_to_device_frame(glm::dvec3 v) { return {v.y, -v.x, v.z}; }
[[nodiscard]] constexpr glm::dvec3 device_to_woodenhaptics_frame(glm::dvec3 v) { return {-v.y, v.x, v.z}; }

// The device. It applies no clamp, ramp or rate limit of its own: SafeForceDevice wraps every
// force-capable device before a hand gets it, and takes max_force_n from capabilities().
class WoodenHapticsDevice final : public HapticDevice {
public:
    WoodenHapticsDevice(std::unique_ptr<HidTransport> transport, WoodenHapticsProfile profile);
    // A last zero current, queued before the transport goes (it writes it before it closes the handle):
    // this firmware keeps its currents for half a second by itself.
    ~WoodenHapticsDevice() override;
    WoodenHapticsDevice(const WoodenHapticsDevice&) = delete;
    WoodenHapticsDevice& operator=(const WoodenHapticsDevice&) = delete;
    [[nodiscard]] const DeviceCapabilities& capabilities() const override { return caps_; }
    [[nodiscard]] WireCounts wire() const override { return transport_->wire(); }
    [[nodiscard]] IoPriority io_priority() const override { return transport_->io_priority(); }
    // Drains the pending reports (at most a bounded number, so a flood cannot hold the loop); a
    // report of the wrong size is counted and skipped. The position is the newest report's, in metres,
    // device frame. The 2017 firmware has no buttons: buttons are always 0.
    Result<DeviceSample> poll(std::int64_t now_us) override;
    // The force (newtons, device frame) as motor currents at the pose of the last poll.
    Result<void> send_force(glm::dvec3 force_n) override;
    // Zero current on all motors. Safe from another thread (the force watchdog's) while send_force runs.
    Result<void> zero_force() override;

    [[nodiscard]] const WoodenHapticsProfile& profile() const noexcept { return profile_; }
    [[nodiscard]] std::uint64_t reports_refused() const noexcept { return refused_; }
    [[nodiscard]] WoodenHapticsCounts last_counts() const noexcept { return counts_; }

private:
    Result<void> write(std::span<const std::uint8_t> report);

    std::unique_ptr<HidTransport> transport_;
    PiMutex write_mutex_; // send_force (haptic loop) and zero_force (watchdog) write the same device
    WoodenHapticsProfile profile_;
    DeviceCapabilities caps_;
    WoodenHapticsCounts counts_{};
    glm::dvec3 angles_{};
    std::uint64_t refused_ = 0;
    std::int64_t report_us_ = std::numeric_limits<std::int64_t>::min(); // when the newest report arrived
};

} // namespace ikebana::devices
