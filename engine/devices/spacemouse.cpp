#include "engine/devices/spacemouse.hpp"

#include <algorithm>

namespace ikebana::devices {

namespace {
std::int16_t le16(const std::uint8_t* p) {
    return static_cast<std::int16_t>(static_cast<std::uint16_t>(p[0] | (p[1] << 8)));
}
} // namespace

const std::vector<SpaceMouseProfile>& spacemouse_profiles() {
    static const std::vector<SpaceMouseProfile> profiles = {
        {0x046d, 0xc603, "SpaceMouse Plus XT", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc605, "CADMan", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc606, "SpaceMouse Classic", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc621, "SpaceBall 5000", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc623, "SpaceTraveler", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc625, "SpacePilot", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc626, "SpaceNavigator", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc627, "SpaceExplorer", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc628, "SpaceNavigator for Notebooks", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc629, "SpacePilot Pro", SpaceMouseReports::split, 350.0},
        {0x046d, 0xc62b, "SpaceMouse Pro", SpaceMouseReports::split, 350.0},
        {0x256f, 0xc62e, "SpaceMouse Wireless (cable)", SpaceMouseReports::combined, 350.0},
        {0x256f, 0xc62f, "SpaceMouse Wireless (receiver)", SpaceMouseReports::combined, 350.0},
        {0x256f, 0xc631, "SpaceMouse Pro Wireless (cable)", SpaceMouseReports::combined, 350.0},
        {0x256f, 0xc632, "SpaceMouse Pro Wireless (receiver)", SpaceMouseReports::combined, 350.0},
        {0x256f, 0xc633, "SpaceMouse Enterprise", SpaceMouseReports::combined, 350.0},
        {0x256f, 0xc635, "SpaceMouse Compact", SpaceMouseReports::combined, 350.0},
        {0x256f, 0xc652, "3Dconnexion Universal Receiver", SpaceMouseReports::combined, 350.0},
    };
    return profiles;
}

std::optional<SpaceMouseProfile> find_spacemouse_profile(std::uint16_t vendor_id, std::uint16_t product_id) {
    for (const auto& p : spacemouse_profiles()) {
        if (p.vendor_id == vendor_id && p.product_id == product_id) return p;
    }
    return std::nullopt;
}

const char* SpaceMouseParser::fault(std::span<const std::uint8_t> report) const noexcept {
    if (report.empty()) return "empty report";
    const std::size_t n = report.size();
    switch (report[0]) {
    case 1:
        if (profile_.reports == SpaceMouseReports::combined && n != 13) return "expected 13 (six axes)";
        if (n != 13 && n != 7) return "expected 7 (translation)";
        return nullptr;
    case 2: return n == 7 ? nullptr : "expected 7 (rotation)";
    case 3: return n >= 2 && n <= 5 ? nullptr : "expected 2 to 5 (buttons)";
    default: return nullptr;
    }
}

ReportOutcome SpaceMouseParser::take(std::span<const std::uint8_t> report) noexcept {
    if (fault(report)) {
        ++refused_;
        return ReportOutcome::refused;
    }
    const std::size_t n = report.size();
    switch (report[0]) {
    case 1:
        if (n == 13) {
            for (int axis = 0; axis < 6; ++axis) axes_[axis] = le16(&report[1 + 2 * static_cast<std::size_t>(axis)]);
        } else {
            for (int axis = 0; axis < 3; ++axis) axes_[axis] = le16(&report[1 + 2 * static_cast<std::size_t>(axis)]);
        }
        return ReportOutcome::updated;
    case 2:
        for (int axis = 0; axis < 3; ++axis) axes_[3 + axis] = le16(&report[1 + 2 * static_cast<std::size_t>(axis)]);
        return ReportOutcome::updated;
    case 3: {
        std::uint32_t bits = 0;
        for (std::size_t i = 1; i < n; ++i) bits |= static_cast<std::uint32_t>(report[i]) << (8 * (i - 1));
        buttons_ = bits;
        return ReportOutcome::updated;
    }
    default: return ReportOutcome::ignored; // LEDs, battery, vendor reports
    }
}

Result<ReportOutcome> SpaceMouseParser::feed(std::span<const std::uint8_t> report) {
    const char* why = fault(report);
    const ReportOutcome outcome = take(report);
    if (outcome != ReportOutcome::refused) return outcome;
    if (report.empty()) return make_error(ErrorCode::device_error, std::string(profile_.name) + ": " + why);
    return make_error(ErrorCode::device_error, std::string(profile_.name) + ": report " + std::to_string(report[0]) + " of " +
                                                   std::to_string(report.size()) + " bytes, " + why);
}

DeviceSample SpaceMouseParser::sample(std::int64_t now_us) const {
    DeviceSample s;
    s.time_us = now_us;
    auto norm = [this](std::int16_t v) { return std::clamp(static_cast<double>(v) / profile_.full_scale, -1.0, 1.0); };
    s.position = {norm(axes_[0]), norm(axes_[1]), norm(axes_[2])};
    s.rotation = {norm(axes_[3]), norm(axes_[4]), norm(axes_[5])};
    s.buttons = buttons_;
    return s;
}

} // namespace ikebana::devices
