#include "game/devices/hand_device_selection.hpp"

#include <algorithm>
#include <cstdlib>

#include "engine/devices/emulated_diy.hpp"
#include "engine/devices/hid_devices.hpp"
#include "engine/devices/reconnecting_device.hpp"
#include "engine/devices/scripted_device.hpp"
#include "game/asset_paths.hpp"

namespace ikebana::game {

namespace {

// Runs on the reconnecting device's own thread (never the 1 kHz one): it enumerates and opens.
Result<std::unique_ptr<devices::HapticDevice>> open_hid(const devices::HidDeviceInfo& info, const devices::WoodenHapticsProfile& woodenhaptics) {
    const auto match = devices::match_hid_device(info);
    auto transport = devices::open_hid_device(info.path);
    if (!transport) return std::move(transport).error();
    if (match.kind == devices::DeviceMatch::Kind::diy_force) {
        return std::unique_ptr<devices::HapticDevice>(std::make_unique<devices::DiyForceDevice>(std::move(transport).value()));
    }
    if (match.kind == devices::DeviceMatch::Kind::woodenhaptics) {
        return std::unique_ptr<devices::HapticDevice>(std::make_unique<devices::WoodenHapticsDevice>(std::move(transport).value(), woodenhaptics));
    }
    if (match.kind == devices::DeviceMatch::Kind::spacemouse) {
        return std::unique_ptr<devices::HapticDevice>(std::make_unique<devices::SpaceMouseDevice>(
            std::move(transport).value(), *devices::find_spacemouse_profile(info.vendor_id, info.product_id)));
    }
    return make_error(ErrorCode::device_error, info.path + ": no hand-device profile for " + std::to_string(info.vendor_id) + ":" +
                                                   std::to_string(info.product_id));
}

bool pushes(devices::DeviceMatch::Kind kind) {
    return kind == devices::DeviceMatch::Kind::diy_force || kind == devices::DeviceMatch::Kind::woodenhaptics;
}

Result<OpenedDevice> reconnecting(const devices::HidDeviceInfo& info) {
    const auto match = devices::match_hid_device(info);
    // A WoodenHaptics' kinematics live on the host, so its geometry comes from a profile file (the
    // builder's own measurements if they gave one, else the published design's): read here, once,
    // not by the opener at every reconnection.
    devices::WoodenHapticsProfile woodenhaptics;
    if (match.kind == devices::DeviceMatch::Kind::woodenhaptics) {
        auto profile = devices::load_woodenhaptics_profile(woodenhaptics_profile_path());
        if (!profile) return std::move(profile).error();
        woodenhaptics = std::move(profile).value();
    }
    // What the device will be while it is away: its profile's name, force, silence limit and coupling.
    devices::DeviceCapabilities expected;
    expected.name = match.profile;
    expected.has_force_output = pushes(match.kind);
    expected.reports_position = expected.has_force_output;
    if (match.kind == devices::DeviceMatch::Kind::diy_force) {
        expected.silent_after_us = devices::diy_silent_after_us;
        expected.max_force_n = devices::diy_max_force_n;
        expected.workspace_half_extent_m = glm::dvec3{devices::diy_workspace_half_extent_m};
        expected.coupling_n_per_m = devices::diy_coupling_n_per_m;
        expected.coupling_damping_ns_per_m = devices::diy_coupling_damping_ns_per_m;
    } else if (match.kind == devices::DeviceMatch::Kind::woodenhaptics) {
        expected.max_force_n = woodenhaptics.max_force_n;
        expected.workspace_half_extent_m = glm::dvec3{woodenhaptics.workspace_radius_m};
        expected.silent_after_us = static_cast<std::int64_t>(woodenhaptics.silent_after_ms * 1000.0);
        expected.max_stiffness_n_per_m = woodenhaptics.max_stiffness_n_per_m;
        expected.max_damping_ns_per_m = woodenhaptics.max_damping_ns_per_m;
    }
    auto device = std::make_unique<devices::ReconnectingDevice>(
        [info, woodenhaptics]() -> Result<std::unique_ptr<devices::HapticDevice>> {
            // Its own path first (two identical devices must not swap hands); plugged back in, a device
            // may come back under another path: then by its ids.
            auto found = devices::enumerate_hid_devices();
            if (!found) return std::move(found).error();
            for (const auto& d : *found) {
                if (d.path == info.path && d.vendor_id == info.vendor_id && d.product_id == info.product_id) return open_hid(d, woodenhaptics);
            }
            for (const auto& d : *found) {
                if (d.vendor_id == info.vendor_id && d.product_id == info.product_id) return open_hid(d, woodenhaptics);
            }
            return make_error(ErrorCode::device_error, info.product + ": not plugged in");
        },
        expected);
    return OpenedDevice{std::move(device), match.profile + " at " + info.path};
}

} // namespace

std::filesystem::path woodenhaptics_profile_path() {
    if (const char* env = std::getenv("IKEBANA_WOODENHAPTICS_PROFILE"); env && *env) return env;
    return asset_dir() / "devices" / "woodenhaptics.json";
}

Result<OpenedDevice> open_hand_device(const std::string& spec, std::uint8_t hand) {
    if (spec == "none") return OpenedDevice{nullptr, "none"};
    const auto colon = spec.find(':');
    const std::string kind = spec.substr(0, colon);
    const std::string arg = colon == std::string::npos ? "" : spec.substr(colon + 1);
    if (kind == "scripted" || kind == "replay") {
        if (arg.empty()) return make_error(ErrorCode::invalid_argument, "'" + spec + "': give a file, e.g. " + kind + ":session.csv");
        const std::filesystem::path file = std::filesystem::exists(arg) ? std::filesystem::path(arg) : asset_path(arg);
        auto keys = devices::load_trajectory(file);
        if (!keys) return std::move(keys).error();
        const auto mode = kind == "replay" ? devices::ScriptedDevice::Mode::replay : devices::ScriptedDevice::Mode::interpolate;
        return OpenedDevice{std::make_unique<devices::ScriptedDevice>(std::move(keys).value(), mode, spec), spec};
    }
    if (kind == "emulated-diy") {
        // The whole chain without hardware: the DIY protocol over the real transport, its reports logged.
        if (arg.empty()) return make_error(ErrorCode::invalid_argument, "'" + spec + "': give a log file, e.g. emulated-diy:forces.log");
        auto transport = devices::open_emulated_diy(arg);
        if (!transport) return std::move(transport).error();
        return OpenedDevice{std::make_unique<devices::DiyForceDevice>(std::move(transport).value()), "emulated DIY device, its forces in " + arg};
    }
    if (kind == "hid" || kind == "auto") {
        auto found = devices::enumerate_hid_devices();
        if (!found) return std::move(found).error();
        if (kind == "hid") {
            for (const auto& d : *found) {
                if (d.path == arg) return reconnecting(d);
            }
            return make_error(ErrorCode::not_found, "'" + arg + "': no such HID device (see `ikebana devices`)");
        }
        std::vector<devices::HidDeviceInfo> usable;
        for (const auto& d : *found) {
            if (devices::match_hid_device(d).kind != devices::DeviceMatch::Kind::unknown) usable.push_back(d);
        }
        // Force devices (DIY, WoodenHaptics) first: a hand that can feel the stem beats one that cannot.
        std::stable_sort(usable.begin(), usable.end(), [](const auto& a, const auto& b) {
            return pushes(devices::match_hid_device(a).kind) && !pushes(devices::match_hid_device(b).kind);
        });
        if (hand < usable.size()) return reconnecting(usable[hand]);
        return OpenedDevice{nullptr, "none found"};
    }
    return make_error(ErrorCode::invalid_argument,
                      "'" + spec + "': expected auto, none, scripted:FILE, replay:FILE, hid:PATH or emulated-diy:LOG");
}

} // namespace ikebana::game
