#pragma once
// Which device drives which hand. Specs, from the command line or the scene:
//   auto           the hand-th usable HID device hidapi finds (force devices first: DIY, WoodenHaptics;
//                  then the SpaceMouse family), re-opened if it is unplugged and plugged back; none found: no device
//   none           no device (the window's mouse and keyboard once the renderer exists)
//   scripted:FILE  a trajectory CSV, interpolated
//   replay:FILE    a recorded session, sample by sample
//   hid:PATH       that HID device (as `ikebana devices` lists it)
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "engine/core/result.hpp"
#include "engine/devices/haptic_device.hpp"

namespace ikebana::game {

struct OpenedDevice {
    std::unique_ptr<devices::HapticDevice> device; // null: no device for this hand
    std::string description;
};

Result<OpenedDevice> open_hand_device(const std::string& spec, std::uint8_t hand);

// The WoodenHaptics profile a WoodenHaptics device is opened with: $IKEBANA_WOODENHAPTICS_PROFILE if
// set, else assets/devices/woodenhaptics.json (the published design).
[[nodiscard]] std::filesystem::path woodenhaptics_profile_path();

} // namespace ikebana::game
