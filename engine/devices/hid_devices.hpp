#pragma once
// HapticDevice backends over a HidTransport: the SpaceMouse family (6-DoF input, no force) and the DIY
// force-feedback device (docs/diy-haptic-protocol.md).
#include <atomic>
#include <limits>
#include <memory>
#include <optional>

#include "engine/devices/diy_protocol.hpp"
#include "engine/devices/haptic_device.hpp"
#include "engine/devices/hid_transport.hpp"
#include "engine/devices/spacemouse.hpp"
#include "engine/devices/woodenhaptics.hpp"

namespace ikebana::devices {

// The DIY device's USB ids (pid.codes' open-source vendor id; change both in firmware and here).
inline constexpr std::uint16_t diy_vendor_id = 0x1209;
inline constexpr std::uint16_t diy_product_id = 0x1d3a;
// The DIY device's profile beyond what its reports say (docs/haptics.md, "Limits per profile"). It
// sends a state report every millisecond (docs/diy-haptic-protocol.md): 20 ms without one is a hung
// device, long before its own 500 ms watchdog would say so. Protocol v1 declares no stiffness limit
// (the builds differ: a delta, a pantograph), so the coupling is the profile's own, a conservative
// 400 N/m and 2 N s/m that a desk-sized build renders without buzzing.
inline constexpr std::int64_t diy_silent_after_us = 20'000;
inline constexpr double diy_max_force_n = 3.0;           // until the device reports its own, lower, limit
inline constexpr double diy_workspace_half_extent_m = 0.08;
inline constexpr double diy_coupling_n_per_m = 400.0;
inline constexpr double diy_coupling_damping_ns_per_m = 2.0;

// Which profile, if any, a HID device matches: for `ikebana devices` and automatic selection.
struct DeviceMatch {
    enum class Kind { spacemouse, diy_force, woodenhaptics, unknown } kind = Kind::unknown;
    std::string profile;
};
[[nodiscard]] DeviceMatch match_hid_device(const HidDeviceInfo& info);

class SpaceMouseDevice final : public HapticDevice {
public:
    SpaceMouseDevice(std::unique_ptr<HidTransport> transport, SpaceMouseProfile profile);
    [[nodiscard]] const DeviceCapabilities& capabilities() const override { return caps_; }
    // Drains every pending report; refused ones are counted and skipped, the device stays usable.
    Result<DeviceSample> poll(std::int64_t now_us) override;
    Result<void> send_force(glm::dvec3) override { return {}; }
    [[nodiscard]] const SpaceMouseParser& parser() const noexcept { return parser_; }
    [[nodiscard]] WireCounts wire() const override { return transport_->wire(); }
    [[nodiscard]] IoPriority io_priority() const override { return transport_->io_priority(); }

private:
    std::unique_ptr<HidTransport> transport_;
    SpaceMouseParser parser_;
    DeviceCapabilities caps_;
};

class DiyForceDevice final : public HapticDevice {
public:
    // The ramp, rate limit and stall handling are SafeForceDevice's, which wraps every force device
    // before a hand gets it; this device only refuses to encode more than its limit or a NaN.
    explicit DiyForceDevice(std::unique_ptr<HidTransport> transport, double max_force_n = diy_max_force_n);
    // A last zero, queued before the transport goes (it writes it before it closes the handle).
    ~DiyForceDevice() override;
    DiyForceDevice(const DiyForceDevice&) = delete;
    DiyForceDevice& operator=(const DiyForceDevice&) = delete;
    // Fixed once made: the limit the device reports later is max_force_now_n().
    [[nodiscard]] const DeviceCapabilities& capabilities() const override { return caps_; }
    [[nodiscard]] double max_force_now_n() const override { return max_force_n_.load(std::memory_order_relaxed); }
    [[nodiscard]] WireCounts wire() const override { return transport_->wire(); }
    [[nodiscard]] IoPriority io_priority() const override { return transport_->io_priority(); }
    Result<DeviceSample> poll(std::int64_t now_us) override;
    // Sends the force (clamped to the device's limit, non-finite as zero) with the next sequence number.
    Result<void> send_force(glm::dvec3 force_n) override;
    // Zero force, motors still enabled: what the watchdog sends. Safe from another thread.
    Result<void> send_zero();
    Result<void> zero_force() override { return send_zero(); }

    [[nodiscard]] const diy::SequenceTracker& sequence() const noexcept { return inbound_; }
    [[nodiscard]] std::uint64_t reports_refused() const noexcept { return refused_; }
    [[nodiscard]] std::uint8_t last_status() const noexcept { return last_.status; }

private:
    std::unique_ptr<HidTransport> transport_;
    std::atomic<double> max_force_n_; // read by the sender and other threads, tightened by poll()
    diy::SequenceTracker inbound_;
    diy::StateReport last_{};
    std::atomic<std::uint16_t> outbound_{0};
    std::uint64_t refused_ = 0;
    std::int64_t report_us_ = std::numeric_limits<std::int64_t>::min(); // when the newest accepted report arrived
    DeviceCapabilities caps_;
};

} // namespace ikebana::devices
