#pragma once
// The devices driving the two hands (a sim-lane resource; the app owns the devices).
#include <array>

#include "components/hand.hpp"
#include "engine/core/async_line_writer.hpp"
#include "engine/devices/force_safety.hpp"
#include "engine/devices/haptic_device.hpp"
#include "engine/devices/scripted_device.hpp"

namespace ikebana::systems {

struct HandDevices {
    std::array<devices::HapticDevice*, 2> device{nullptr, nullptr};
    // Per hand, the spring between the device and the proxy cube (N/m: what pressing on a rigid thing
    // feels like) and its damping (N s/m, on the proxy's motion relative to the device's): the device
    // profile's, capped by the stiffness and damping the device renders stably (set when it is attached).
    std::array<double, 2> coupling_n_per_m{400.0, 400.0};
    std::array<double, 2> coupling_damping_ns_per_m{2.0, 2.0};

    // When set, every sample each device produces is recorded with its time (a session to replay).
    std::array<devices::DeviceRecorder*, 2> recorder{nullptr, nullptr};
    // With the recorders: when a device goes away and when it is back, one CSV line each
    // ("time_us,gone,hand,0", "time_us,back,hand,0": a session's commands.csv), so that a replay's
    // device is away for the same ticks (its samples alone cannot say so).
    AsyncLineWriter* events = nullptr;
    // In real time: fed after every force sent, so that a stalled loop gets its devices zeroed.
    std::array<devices::ForceWatchdog*, 2> watchdog{nullptr, nullptr};
};

// What each hand's device link is doing and how many force writes failed, for the HUD and the figures
// (a sim-lane resource). Written by hand_input and the force systems. Not simulation state, so kept
// out of the components and the state hash: a replay's devices never fall silent, and it must still
// agree with the session.
struct HandLinks {
    std::array<components::DeviceLink, 2> link{components::DeviceLink::not_answering, components::DeviceLink::not_answering};
    std::array<std::uint64_t, 2> write_failures{0, 0};
};

} // namespace ikebana::systems
