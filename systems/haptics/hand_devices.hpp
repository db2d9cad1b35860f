#pragma once
// The devices driving the two hands (a sim-lane resource; the app owns the devices).
#include <array>
#include <ostream>

#include "engine/devices/force_safety.hpp"
#include "engine/devices/haptic_device.hpp"
#include "engine/devices/scripted_device.hpp"

namespace ikebana::systems {

struct HandDevices {
    std::array<devices::HapticDevice*, 2> device{nullptr, nullptr};
    // Spring between the device and the proxy cube (N/m): what pressing on a rigid thing feels like.
    double coupling_n_per_m = 400.0;
    // Damping of the coupling (N s/m): the proxy's motion relative to the device's.
    double coupling_damping_n_s_per_m = 2.0;
    // When set, every sample each device produces is recorded with its time (a session to replay).
    std::array<devices::DeviceRecorder*, 2> recorder{nullptr, nullptr};
    // With the recorders: when a device goes away and when it is back, one CSV line each
    // ("time_us,gone,hand,0", "time_us,back,hand,0": a session's commands.csv), so that a replay's
    // device is away for the same ticks (its samples alone cannot say so).
    std::ostream* events = nullptr;
    // In real time: fed after every force sent, so that a stalled loop gets its devices zeroed.
    std::array<devices::ForceWatchdog*, 2> watchdog{nullptr, nullptr};
};

} // namespace ikebana::systems
