#include "engine/devices/hid_transport.hpp"

#include <mutex>

#include <hidapi/hidapi.h>

#include "engine/core/pi_mutex.hpp"

namespace ikebana::devices {

namespace {

std::string narrow(const wchar_t* text) {
    std::string out;
    if (!text) return out;
    for (; *text; ++text) out += *text < 128 ? static_cast<char>(*text) : '?';
    return out;
}

Result<void> init_once() {
    static std::once_flag once;
    static int status = 0;
    std::call_once(once, [] { status = hid_init(); });
    if (status != 0) return make_error(ErrorCode::device_error, "hidapi could not be initialised");
    return {};
}

class HidapiTransport final : public HidTransport {
public:
    HidapiTransport(hid_device* device, std::string path) : device_(device), path_(std::move(path)) {}
    ~HidapiTransport() override { hid_close(device_); }

    Result<std::size_t> read(std::span<std::uint8_t> buffer, int timeout_ms) override {
        const int n = hid_read_timeout(device_, buffer.data(), buffer.size(), timeout_ms);
        if (n < 0) return make_error(ErrorCode::device_error, path_ + ": read failed (unplugged?)");
        return static_cast<std::size_t>(n);
    }
    Result<void> write(std::span<const std::uint8_t> report) override {
        // The device may be written from the haptic loop and from the force watchdog's thread: a
        // priority-inheriting lock, held for one report's write.
        const std::lock_guard lock(write_mutex_);
        if (hid_write(device_, report.data(), report.size()) < 0) {
            return make_error(ErrorCode::device_error, path_ + ": write failed (unplugged?)");
        }
        return {};
    }

private:
    hid_device* device_;
    std::string path_;
    PiMutex write_mutex_;
};

} // namespace

Result<std::vector<HidDeviceInfo>> enumerate_hid_devices() {
    if (auto ok = init_once(); !ok) return std::move(ok).error();
    std::vector<HidDeviceInfo> out;
    hid_device_info* list = hid_enumerate(0, 0);
    for (hid_device_info* d = list; d; d = d->next) {
        out.push_back({d->vendor_id, d->product_id, d->path ? d->path : "", narrow(d->manufacturer_string), narrow(d->product_string)});
    }
    hid_free_enumeration(list);
    return out;
}

Result<std::unique_ptr<HidTransport>> open_hid_device(const std::string& path) {
    if (auto ok = init_once(); !ok) return std::move(ok).error();
    hid_device* device = hid_open_path(path.c_str());
    if (!device) return make_error(ErrorCode::device_error, path + ": cannot be opened (permissions? see docs/haptics.md, 'Checking it')");
    return std::unique_ptr<HidTransport>(std::make_unique<HidapiTransport>(device, path));
}

} // namespace ikebana::devices
