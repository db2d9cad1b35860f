#pragma once
// The devices driving the two hands (a sim-lane resource; the app owns the devices).
#include <array>

#include "engine/devices/haptic_device.hpp"

namespace ikebana::systems {

struct HandDevices {
    std::array<devices::HapticDevice*, 2> device{nullptr, nullptr};
    // Spring between the device and the proxy cube (N/m): what pressing on a rigid thing feels like.
    double coupling_n_per_m = 400.0;
};

} // namespace ikebana::systems
