#pragma once
// Scripted hands for the end-to-end haptics tests: a device that follows keyframes.
#include <memory>
#include <vector>

#include "engine/devices/scripted_device.hpp"

namespace ikebana::test {

// A keyframe as (t, x, y, z, buttons); seconds and metres in the world frame.
struct Key {
    double t, x, y, z;
    int buttons;
};

// A device that moves between the keys in straight lines.
std::unique_ptr<devices::ScriptedDevice> script(const std::vector<Key>& keys);

} // namespace ikebana::test
