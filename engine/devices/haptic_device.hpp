#pragma once
// One interface for every input device a hand can be driven by: 6-DoF pose, buttons, force output and
// what the device can do. Backends: hidapi (SpaceMouse family, the DIY force-feedback device),
// mouse + keyboard, scripted trajectories, replay. Device logic is kept apart from the bytes on the
// wire (see hid_transport.hpp) so that it is tested on fixtures.
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "engine/core/result.hpp"

namespace ikebana::devices {

struct DeviceCapabilities {
    std::string name;
    bool has_force_output = false;
    double max_force_n = 0.0;              // the device's own limit; never exceeded (force_safety.hpp)
    glm::dvec3 workspace_half_extent_m{0.0}; // reachable box around the device's centre
    // Position devices report where the handle is; rate devices (a SpaceMouse) report a push that the
    // hand integrates into motion.
    bool reports_position = true;
    // A scripted or replayed hand: its time is the trajectory's and its forces are recorded, not felt.
    // It still gets the safety chain, on that time, so a recording shows what a device would have felt.
    bool on_timeline = false;
};

struct DeviceSample {
    std::int64_t time_us = 0;
    glm::dvec3 position{0.0};  // metres for position devices; normalised push in [-1, 1] for rate devices
    glm::dvec3 rotation{0.0};  // radians (position devices) or normalised twist in [-1, 1] (rate devices)
    std::uint32_t buttons = 0; // bit i: button i pressed
};

class HapticDevice {
public:
    virtual ~HapticDevice() = default;
    [[nodiscard]] virtual const DeviceCapabilities& capabilities() const = 0;
    // Reads whatever the device has sent since the last call; an error means it is gone (unplugged).
    virtual Result<DeviceSample> poll(std::int64_t now_us) = 0;
    // Sends a force already made safe by ForceSafety; devices without force output ignore it.
    virtual Result<void> send_force(glm::dvec3 force_n) = 0;
    // Zero force now. Unlike send_force this may be called from another thread (the force watchdog's).
    virtual Result<void> zero_force() { return {}; }
};

} // namespace ikebana::devices
