#pragma once
// The only code that talks to hidapi. Everything above it takes a HidTransport, so device logic is
// tested with a fake transport and byte fixtures (this machine has no USB and no /dev/uhid).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/core/result.hpp"

namespace ikebana::devices {

struct HidDeviceInfo {
    std::uint16_t vendor_id = 0;
    std::uint16_t product_id = 0;
    std::string path;
    std::string manufacturer;
    std::string product;
};

class HidTransport {
public:
    virtual ~HidTransport() = default;
    // Reads one report into `buffer`; 0 bytes when none arrived within `timeout_ms`. An error means the
    // device is gone.
    virtual Result<std::size_t> read(std::span<std::uint8_t> buffer, int timeout_ms) = 0;
    virtual Result<void> write(std::span<const std::uint8_t> report) = 0;
};

// What hidapi sees now (empty, not an error, on a machine without HID devices).
Result<std::vector<HidDeviceInfo>> enumerate_hid_devices();
Result<std::unique_ptr<HidTransport>> open_hid_device(const std::string& path);

} // namespace ikebana::devices
