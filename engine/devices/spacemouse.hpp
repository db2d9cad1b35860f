#pragma once
// The 3Dconnexion SpaceMouse family over raw HID, as a 6-DoF input without force. Older models send
// translation in report 1 (7 bytes: id, x, y, z as little-endian int16), rotation in report 2 and
// buttons in report 3 (a bitmask); newer ones send all six axes in one 13-byte report 1. Other report
// ids (LEDs, battery) are ignored; a report of the wrong length is refused and changes nothing.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include "engine/devices/haptic_device.hpp"

namespace ikebana::devices {

enum class SpaceMouseReports : std::uint8_t {
    split,    // report 1 translation, report 2 rotation
    combined, // report 1 carries all six axes
};

struct SpaceMouseProfile {
    std::uint16_t vendor_id;
    std::uint16_t product_id;
    const char* name;
    SpaceMouseReports reports;
    double full_scale; // raw axis value that means a full push
};

// The models we know; vendor ids 0x046d (Logitech-era) and 0x256f (3Dconnexion).
[[nodiscard]] const std::vector<SpaceMouseProfile>& spacemouse_profiles();
[[nodiscard]] std::optional<SpaceMouseProfile> find_spacemouse_profile(std::uint16_t vendor_id, std::uint16_t product_id);

enum class ReportOutcome : std::uint8_t { updated, ignored, refused };

class SpaceMouseParser {
public:
    explicit SpaceMouseParser(SpaceMouseProfile profile) : profile_(profile) {}

    // One HID report, its first byte the report id. Errors name what was wrong with it (in words,
    // which allocate: for tests and diagnostics).
    Result<ReportOutcome> feed(std::span<const std::uint8_t> report);
    // The same without words, for the 1 kHz thread: a refused report is counted and said `refused`.
    ReportOutcome take(std::span<const std::uint8_t> report) noexcept;

    // The current push and twist, each axis in [-1, 1], and the buttons.
    [[nodiscard]] DeviceSample sample(std::int64_t now_us) const;
    [[nodiscard]] std::uint64_t reports_refused() const noexcept { return refused_; }

private:
    // Why `report` is refused (nullptr: it is not), and the size it should have had.
    [[nodiscard]] const char* fault(std::span<const std::uint8_t> report) const noexcept;

    SpaceMouseProfile profile_;
    std::int16_t axes_[6]{};
    std::uint32_t buttons_ = 0;
    std::uint64_t refused_ = 0;
};

} // namespace ikebana::devices
