// libFuzzer: bytes from a USB device, into each hand device's decoder: the SpaceMouse family's
// reports (one profile per input family), the DIY protocol's state and force reports, and
// WoodenHaptics' encoder report. The first byte picks the decoder; the rest is the report.
#include <span>

#include "engine/devices/diy_protocol.hpp"
#include "engine/devices/spacemouse.hpp"
#include "engine/devices/woodenhaptics.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const std::span<const std::uint8_t> report(data + 1, size - 1);
    const auto& profiles = devices::spacemouse_profiles();
    switch (data[0] % 4) {
    case 0: {
        devices::SpaceMouseParser parser(profiles[data[0] / 4 % profiles.size()]);
        // A stream of reports: split the bytes at every 0xff, as a device sends one after another.
        std::size_t start = 0;
        for (std::size_t i = 0; i <= report.size(); ++i) {
            if (i == report.size() || report[i] == 0xff) {
                (void)parser.feed(report.subspan(start, i - start));
                start = i + 1;
            }
        }
        const auto s = parser.sample(0);
        (void)s;
        break;
    }
    case 1: (void)devices::diy::decode_state(report); break;
    case 2: (void)devices::diy::decode_force(report); break;
    case 3: {
        const devices::WoodenHapticsProfile profile{};
        if (const auto counts = devices::decode_woodenhaptics_report(report)) {
            const auto angles = devices::woodenhaptics_angles(profile, *counts);
            (void)devices::woodenhaptics_position(profile, angles);
            (void)devices::encode_woodenhaptics_currents(devices::woodenhaptics_currents(profile, angles, {1.0, -2.0, 3.0}));
        }
        break;
    }
    }
    return 0;
}
