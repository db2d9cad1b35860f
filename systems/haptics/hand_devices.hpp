#pragma once
// The devices driving the two hands (a sim-lane resource; the app owns the devices).
#include <array>
#include <cstddef>

#include "components/hand.hpp"
#include "engine/core/async_line_writer.hpp"
#include "engine/devices/force_safety.hpp"
#include "engine/devices/haptic_device.hpp"
#include "engine/devices/scripted_device.hpp"

namespace ikebana::systems {

// Per hand, the spring between the device and the proxy cube (N/m: what pressing on a rigid thing
// feels like) and its damping (N s/m, on the proxy's motion relative to the device's): the device
// profile's, capped by the stiffness and damping the device renders stably (set when it is attached).
// Plain data (a sim-lane resource): the force systems read it without touching the devices.
struct HandCoupling {
    std::array<double, 2> n_per_m{400.0, 400.0};
    std::array<double, 2> damping_ns_per_m{2.0, 2.0};
};

// The devices driving the two hands, and where their traffic is recorded (a sim-lane resource; the app
// owns the devices). Polling, sending, recording and feeding the watchdog all change something outside
// the registry, so they are reached only through a non-const HandDevices: a system that does any of
// them declares HandDevices written, and the registry holds it to that. A const HandDevices says only
// what a device is and what it was last sent.
class HandDevices {
public:
    // Set-up, outside the systems (the world, the session recorder, the watchdogs). Null detaches.
    void attach(std::size_t hand, devices::HapticDevice* device) noexcept { device_[hand] = device; }
    // When set, every sample each device produces is recorded with its time (a session to replay).
    void record_to(std::size_t hand, devices::DeviceRecorder* recorder) noexcept { recorder_[hand] = recorder; }
    // With the recorders: when a device goes away and when it is back, one CSV line each
    // ("time_us,gone,hand,0", "time_us,back,hand,0": a session's commands.csv), so that a replay's
    // device is away for the same ticks (its samples alone cannot say so).
    void note_events_to(AsyncLineWriter* events) noexcept { events_ = events; }
    // In real time: fed after every force sent, so that a stalled loop gets its devices zeroed.
    void feed_after_sending(std::size_t hand, devices::ForceWatchdog* watchdog) noexcept { watchdog_[hand] = watchdog; }

    // I/O (a write of this resource): null where nothing is attached.
    [[nodiscard]] devices::HapticDevice* device(std::size_t hand) noexcept { return hand < 2 ? device_[hand] : nullptr; }
    [[nodiscard]] devices::DeviceRecorder* recorder(std::size_t hand) noexcept { return hand < 2 ? recorder_[hand] : nullptr; }
    [[nodiscard]] AsyncLineWriter* events() noexcept { return events_; }
    [[nodiscard]] devices::ForceWatchdog* watchdog(std::size_t hand) noexcept { return hand < 2 ? watchdog_[hand] : nullptr; }

    // Reading: whether a hand has a device, and the force its safety chain last sent it.
    [[nodiscard]] bool attached(std::size_t hand) const noexcept { return hand < 2 && device_[hand]; }
    [[nodiscard]] devices::SentForce last_sent(std::size_t hand) const { return attached(hand) ? device_[hand]->last_sent() : devices::SentForce{}; }

private:
    std::array<devices::HapticDevice*, 2> device_{nullptr, nullptr};
    std::array<devices::DeviceRecorder*, 2> recorder_{nullptr, nullptr};
    AsyncLineWriter* events_ = nullptr;
    std::array<devices::ForceWatchdog*, 2> watchdog_{nullptr, nullptr};
};

// A restored sim registry keeps the devices, recorders and watchdogs attached to it (ecs::Registry::
// restore): a replay's saved moment may come from another playback of the same recording.
inline void restore_resource(HandDevices&, HandDevices&&) noexcept {}

// What each hand's device link is doing and how many force writes failed, for the HUD and the figures
// (a sim-lane resource). Written by hand_input and the force systems. Not simulation state, so kept
// out of the components and the state hash: a replay's devices never fall silent, and it must still
// agree with the session.
struct HandLinks {
    std::array<components::DeviceLink, 2> link{components::DeviceLink::not_answering, components::DeviceLink::not_answering};
    std::array<std::uint64_t, 2> write_failures{0, 0};
};

} // namespace ikebana::systems
