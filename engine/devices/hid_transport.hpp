#pragma once
// The only code that talks to hidapi. Everything above it takes a HidTransport, so device logic is
// tested with a fake transport and byte fixtures (this machine has no USB and no /dev/uhid), and the
// real transport itself is tested through a shim of the hidapi calls it makes (HidApi below).
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/result.hpp"
#include "engine/devices/wire.hpp"

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
    // device is gone. With `timeout_ms` 0 (the 1 kHz thread's) it never blocks and never allocates.
    virtual Result<std::size_t> read(std::span<std::uint8_t> buffer, int timeout_ms) = 0;
    // Hands the report over to be written; never blocks for the device and never allocates.
    virtual Result<void> write(std::span<const std::uint8_t> report) = 0;
    [[nodiscard]] virtual WireCounts wire() const { return {}; }
    [[nodiscard]] virtual IoPriority io_priority() const { return IoPriority::none; }
};

// The hidapi calls HidapiTransport makes on an open handle, behind function pointers: the real ones,
// or a test's shim that checks who calls them and when (hidapi 0.13 frees and replaces a handle's one
// error string in every call: two threads in calls on one handle can free it twice).
struct HidApi {
    int (*read_timeout)(void* handle, unsigned char* data, std::size_t length, int milliseconds) = nullptr;
    int (*write)(void* handle, const unsigned char* data, std::size_t length) = nullptr;
    void (*close)(void* handle) = nullptr;
};
[[nodiscard]] const HidApi& real_hidapi();

// The real-time priority the transports' I/O threads ask for: just below the haptic lane's, so a
// report the lane queued is written before the renderer's threads run (on two cores they delay a
// normal-priority thread by milliseconds, past the DIY firmware's 2 ms zeroing).
inline constexpr int haptic_lane_fifo_priority = 20;
inline constexpr int hid_io_fifo_priority = haptic_lane_fifo_priority - 1;

struct HidTransportOptions {
    int fifo_priority = hid_io_fifo_priority; // 0: normal scheduling
    // How long closing waits for the last report (the zero a chain queues as it ends) to be written.
    // A write stuck past it is said, and the handle is closed by the I/O thread once the write returns.
    std::chrono::milliseconds close_wait{200};
    // Where that is said (stderr when empty). Called off the 1 kHz thread.
    std::function<void(std::string_view)> say;
};

// A transport over an open handle. One thread of its own owns the handle: every read, write and the
// close happen there, never two at once. The caller's read() takes reports that thread has read from
// a lock-free queue; write() leaves the newest report in a mailbox and wakes it (sem_post: an atomic
// and, only when the thread sleeps, a futex wake, which never blocks).
[[nodiscard]] std::unique_ptr<HidTransport> make_hidapi_transport(const HidApi& api, void* handle, std::string path,
                                                                  HidTransportOptions options = {});

// What hidapi sees now (empty, not an error, on a machine without HID devices).
Result<std::vector<HidDeviceInfo>> enumerate_hid_devices();
Result<std::unique_ptr<HidTransport>> open_hid_device(const std::string& path);

} // namespace ikebana::devices
