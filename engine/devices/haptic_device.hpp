#pragma once
// One interface for every input device a hand can be driven by: 6-DoF pose, buttons, force output and
// what the device can do. Backends: hidapi (SpaceMouse family, the DIY force-feedback device),
// mouse + keyboard, scripted trajectories, replay. Device logic is kept apart from the bytes on the
// wire (see hid_transport.hpp) so that it is tested on fixtures.
#include <cstdint>
#include <limits>
#include <string>

#include <glm/glm.hpp>

#include "engine/core/result.hpp"
#include "engine/devices/wire.hpp"

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
    // A pushing device that has sent no new report for this long is silent (a firmware hang, a USB
    // stall): its hand lets go and its force fades to zero until reports come again. 0: never checked
    // (a device that reports only when moved, or one not on a wire).
    std::int64_t silent_after_us = 0;
    // The virtual coupling this profile wants between the device and the hand cube, and the most the
    // device renders stably (0: it does not say). The hand gets the lower of the two: above its
    // maximum stiffness a device goes unstable and buzzes.
    double coupling_n_per_m = 400.0;
    double coupling_damping_ns_per_m = 2.0;
    double max_stiffness_n_per_m = 0.0;
    double max_damping_ns_per_m = 0.0;
};

// The coupling a hand gets with this device: the profile's, capped by what the device declares.
[[nodiscard]] inline double coupling_stiffness_n_per_m(const DeviceCapabilities& c) {
    return c.max_stiffness_n_per_m > 0.0 && c.max_stiffness_n_per_m < c.coupling_n_per_m ? c.max_stiffness_n_per_m : c.coupling_n_per_m;
}
[[nodiscard]] inline double coupling_damping_ns_per_m(const DeviceCapabilities& c) {
    return c.max_damping_ns_per_m > 0.0 && c.max_damping_ns_per_m < c.coupling_damping_ns_per_m ? c.max_damping_ns_per_m : c.coupling_damping_ns_per_m;
}

struct DeviceSample {
    std::int64_t time_us = 0;
    glm::dvec3 position{0.0};  // metres for position devices; normalised push in [-1, 1] for rate devices
    glm::dvec3 rotation{0.0};  // radians (position devices) or normalised twist in [-1, 1] (rate devices)
    std::uint32_t buttons = 0; // bit i: button i pressed
    // When the newest report in this sample arrived, on the clock poll() was given. A device that holds
    // its last report when nothing new came keeps this time, so the sample says how old it is. Unset:
    // as fresh as time_us (a scripted hand, the mouse).
    std::int64_t report_us = std::numeric_limits<std::int64_t>::min();
    [[nodiscard]] std::int64_t report_time_us() const noexcept { return report_us == std::numeric_limits<std::int64_t>::min() ? time_us : report_us; }
};

// Why the force that left differs from the one asked for (the largest reason), for the HUD.
enum class ForceHeld : std::uint8_t {
    none,          // sent as asked
    waiting,       // not engaged yet: waiting for the request to be small for a moment
    ramping,       // engaged, the ramp's level below the request
    at_limit,      // clamped to the device's maximum
    rate_limited,  // catching up at the rate limit
    fading,        // going to zero: the device fell silent or stopped taking forces
};

// What became of the last force sent, after the safety chain (SafeForceDevice); a device outside the
// chain (the mouse) sends nothing.
struct SentForce {
    glm::dvec3 sent_n{0.0};     // on the wire: the force of the last report the device was written
    glm::dvec3 queued_n{0.0};   // the last force the chain let out, which may still wait to be written
    double max_force_n = 0.0;   // the chain's limit now (the lower of ours and the device's)
    ForceHeld held = ForceHeld::none; // why it differs from the request
    bool pushes = false;        // this device is on the safety chain (a real one, or a scripted hand's "would feel")
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
    // The host gave up on this device (its writes kept failing): one that can be opened again lets it
    // go at once and opens it anew (off the calling thread), and says true: whatever it answers next
    // comes from the new one. Others say false. From the haptic thread.
    virtual bool drop() { return false; }
    // The force the last send_force put on the wire, after the safety chain.
    [[nodiscard]] virtual SentForce last_sent() const { return {}; }
    // The force limit now: capabilities()' unless the device has since reported a lower one. Safe from
    // any thread (capabilities() never changes once a device is made; this may).
    [[nodiscard]] virtual double max_force_now_n() const { return capabilities().max_force_n; }
    // Its transport's reports (queued and written) and I/O thread; nothing for a device not on a wire.
    [[nodiscard]] virtual WireCounts wire() const { return {}; }
    [[nodiscard]] virtual IoPriority io_priority() const { return IoPriority::none; }
};

} // namespace ikebana::devices
