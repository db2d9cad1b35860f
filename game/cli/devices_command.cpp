#include "game/cli/devices_command.hpp"

#include <cstdio>
#include <iostream>

#include "engine/devices/hid_devices.hpp"
#include "game/devices/hand_device_selection.hpp"

namespace ikebana::game {

void add_devices_command(CLI::App& app, int& exit_code) {
    auto* cmd = app.add_subcommand("devices", "List the HID devices hidapi sees and which hand device profile each matches");
    cmd->callback([&exit_code] {
        const auto found = devices::enumerate_hid_devices();
        if (!found) {
            std::cerr << "ikebana devices: " << found.error().message << "\n";
            exit_code = 2;
            return;
        }
        std::size_t usable = 0;
        for (const auto& d : *found) {
            const auto match = devices::match_hid_device(d);
            usable += match.kind != devices::DeviceMatch::Kind::unknown;
            std::printf("%04x:%04x  %-28s %-24s %s\n", d.vendor_id, d.product_id,
                        match.kind == devices::DeviceMatch::Kind::unknown ? "(no profile)" : match.profile.c_str(),
                        d.product.c_str(), d.path.c_str());
            if (match.kind == devices::DeviceMatch::Kind::woodenhaptics) {
                // Its geometry is a file on the host: say which one and whether it reads.
                const auto file = woodenhaptics_profile_path();
                const auto profile = devices::load_woodenhaptics_profile(file);
                if (profile) std::printf("           profile \"%s\" from %s\n", profile->name.c_str(), file.string().c_str());
                else std::printf("           profile %s does not load:\n%s\n", file.string().c_str(), profile.error().message.c_str());
            }
        }
        std::printf("%zu HID device(s), %zu usable as hands%s\n", found->size(), usable,
                    usable == 0 ? "; the app falls back to mouse and keyboard" : "");
    });
}

} // namespace ikebana::game
