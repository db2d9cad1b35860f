#include "engine/devices/hid_devices.hpp"

#include <array>
#include <cmath>

namespace ikebana::devices {

DeviceMatch match_hid_device(const HidDeviceInfo& info) {
    if (const auto p = find_spacemouse_profile(info.vendor_id, info.product_id)) return {DeviceMatch::Kind::spacemouse, p->name};
    if (info.vendor_id == diy_vendor_id && info.product_id == diy_product_id) {
        return {DeviceMatch::Kind::diy_force, "DIY force-feedback device (protocol v1)"};
    }
    if (info.vendor_id == woodenhaptics_vendor_id && info.product_id == woodenhaptics_product_id) {
        return {DeviceMatch::Kind::woodenhaptics, "WoodenHaptics (raw HID)"};
    }
    return {};
}

SpaceMouseDevice::SpaceMouseDevice(std::unique_ptr<HidTransport> transport, SpaceMouseProfile profile)
    : transport_(std::move(transport)), parser_(profile) {
    caps_.name = profile.name;
    caps_.has_force_output = false;
    caps_.reports_position = false;
}

Result<DeviceSample> SpaceMouseDevice::poll(std::int64_t now_us) {
    std::array<std::uint8_t, 64> buffer{};
    for (int i = 0; i < 64; ++i) { // a bounded drain: a flood of reports cannot hold the loop
        auto n = transport_->read(buffer, 0);
        if (!n) return std::move(n).error();
        if (*n == 0) break;
        (void)parser_.take(std::span<const std::uint8_t>(buffer.data(), *n));
    }
    return parser_.sample(now_us);
}

DiyForceDevice::DiyForceDevice(std::unique_ptr<HidTransport> transport, double max_force_n)
    : transport_(std::move(transport)), max_force_n_(max_force_n) {
    caps_.name = "DIY force-feedback device";
    caps_.has_force_output = true;
    caps_.max_force_n = max_force_n;
    caps_.workspace_half_extent_m = glm::dvec3{diy_workspace_half_extent_m};
    caps_.reports_position = true;
    caps_.silent_after_us = diy_silent_after_us;
    caps_.coupling_n_per_m = diy_coupling_n_per_m;
    caps_.coupling_damping_ns_per_m = diy_coupling_damping_ns_per_m;
}

DiyForceDevice::~DiyForceDevice() { (void)send_zero(); }

Result<DeviceSample> DiyForceDevice::poll(std::int64_t now_us) {
    std::array<std::uint8_t, 64> buffer{};
    for (int i = 0; i < 16; ++i) {
        auto n = transport_->read(buffer, 0);
        if (!n) return std::move(n).error();
        if (*n == 0) break;
        diy::StateReport report{};
        if (diy::decode_state(std::span<const std::uint8_t>(buffer.data(), *n), report) != diy::FrameFault::none || !inbound_.accept(report.sequence)) {
            ++refused_;
            continue;
        }
        last_ = report;
        report_us_ = now_us;
        // The device's own limit tightens ours (never loosens it). capabilities() stays as made: other
        // threads read it while this one polls.
        if (last_.max_force_n > 0.0 && last_.max_force_n < max_force_n_.load(std::memory_order_relaxed)) {
            max_force_n_.store(last_.max_force_n, std::memory_order_relaxed);
        }
    }
    // Until the first report, silence is measured from the first poll.
    if (report_us_ == std::numeric_limits<std::int64_t>::min()) report_us_ = now_us;
    DeviceSample s;
    s.time_us = now_us;
    s.report_us = report_us_; // the last good report's time, not now's: a hung device shows its age
    s.position = glm::dvec3(last_.position_um) * 1e-6;
    s.rotation = glm::dvec3(last_.rotation_mrad) * 1e-3;
    s.buttons = last_.buttons;
    return s;
}

Result<void> DiyForceDevice::send_force(glm::dvec3 force_n) {
    const bool finite = std::isfinite(force_n.x) && std::isfinite(force_n.y) && std::isfinite(force_n.z);
    glm::dvec3 safe = finite ? force_n : glm::dvec3{0.0};
    const double limit = max_force_n_.load();
    if (const double magnitude = glm::length(safe); magnitude > limit) safe *= limit / magnitude;
    const auto bytes = diy::encode_force(diy::ForceReport{static_cast<std::uint16_t>(outbound_.fetch_add(1) + 1), safe, true, 2});
    return transport_->write(bytes);
}

Result<void> DiyForceDevice::send_zero() {
    const auto bytes = diy::encode_force(diy::ForceReport{static_cast<std::uint16_t>(outbound_.fetch_add(1) + 1), glm::dvec3{0.0}, true, 2});
    return transport_->write(bytes);
}

} // namespace ikebana::devices
