#include "engine/devices/hid_transport.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include <hidapi/hidapi.h>

#include "engine/core/pi_mutex.hpp"
#include "engine/sched/triple_buffer.hpp"

namespace ikebana::devices {

namespace {

std::string narrow(const wchar_t* text) {
    std::string out;
    if (!text) return out;
    for (; *text; ++text) out += *text < 128 ? static_cast<char>(*text) : '?';
    return out;
}

// hidapi's enumerate, open and close call hid_init, which frees and sets a global error string with no
// lock (hidapi 0.13): two reconnecting devices' opener threads, or one of them and the main thread,
// must not be in them at once. The 1 kHz thread never takes this lock: it only reads and hands its
// writes to the transport's writer.
std::mutex& bus_mutex() {
    static std::mutex m;
    return m;
}

Result<void> init_once() {
    static std::once_flag once;
    static int status = 0;
    std::call_once(once, [] { status = hid_init(); });
    if (status != 0) return make_error(ErrorCode::device_error, "hidapi could not be initialised");
    return {};
}

// Linux's hidraw write() waits for the USB transfer: on a stalled hub, for seconds. The 1 kHz thread
// (and the watchdog) therefore only leave the newest report in a mailbox; a writer thread of the
// transport's own sends it. A newer report replaces one not yet sent: each carries the whole force,
// so the newest is the one that matters. A write that failed, or one the writer has been stuck in
// for longer than `stalled_after`, makes the next write() fail: the safety chain counts that, and
// after a few in a row drops the device (it is closed on the opener's thread, which then waits for
// the writer, never the 1 kHz thread).
class HidapiTransport final : public HidTransport {
public:
    static constexpr std::size_t max_report_bytes = 64;
    static constexpr auto stalled_after = std::chrono::milliseconds(20);

    HidapiTransport(hid_device* device, std::string path) : device_(device), path_(std::move(path)), writer_([this] { write_loop(); }) {}
    ~HidapiTransport() override {
        stop_.store(true, std::memory_order_release);
        writer_.join();
        const std::lock_guard lock(bus_mutex());
        hid_close(device_);
    }

    Result<std::size_t> read(std::span<std::uint8_t> buffer, int timeout_ms) override {
        const int n = hid_read_timeout(device_, buffer.data(), buffer.size(), timeout_ms);
        if (n < 0) return make_error(ErrorCode::device_error, path_ + ": read failed (unplugged?)");
        return static_cast<std::size_t>(n);
    }
    Result<void> write(std::span<const std::uint8_t> report) override {
        if (report.size() > max_report_bytes) return make_error(ErrorCode::invalid_argument, path_ + ": report longer than 64 bytes");
        {
            // The loop and the watchdog may both write: a priority-inheriting lock, held for a copy.
            const std::lock_guard lock(mailbox_mutex_);
            Report& r = mailbox_.write_buffer();
            std::copy(report.begin(), report.end(), r.bytes.begin());
            r.size = report.size();
            mailbox_.publish();
        }
        if (failed_.exchange(false, std::memory_order_acq_rel)) return make_error(ErrorCode::device_error, path_ + ": write failed (unplugged?)");
        const std::int64_t since = writing_since_ns_.load(std::memory_order_acquire);
        if (since != 0 && now_ns() - since > std::chrono::nanoseconds(stalled_after).count()) {
            return make_error(ErrorCode::device_error, path_ + ": a write has been waiting for the device for over 20 ms");
        }
        return {};
    }

private:
    struct Report {
        std::array<std::uint8_t, max_report_bytes> bytes{};
        std::size_t size = 0;
    };
    static std::int64_t now_ns() {
        return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
    }
    void write_loop() {
        while (!stop_.load(std::memory_order_acquire)) {
            if (!mailbox_.update()) {
                // A report a millisecond: looking every quarter of one costs nothing and takes no lock.
                std::this_thread::sleep_for(std::chrono::microseconds(250));
                continue;
            }
            const Report& r = mailbox_.read_buffer();
            writing_since_ns_.store(now_ns(), std::memory_order_release);
            const int written = hid_write(device_, r.bytes.data(), r.size);
            writing_since_ns_.store(0, std::memory_order_release);
            if (written < 0) failed_.store(true, std::memory_order_release);
        }
    }

    hid_device* device_;
    std::string path_;
    PiMutex mailbox_mutex_;
    sched::TripleBuffer<Report> mailbox_;
    std::atomic<bool> failed_{false};
    std::atomic<std::int64_t> writing_since_ns_{0};
    std::atomic<bool> stop_{false};
    std::thread writer_; // last: it starts when everything it uses is there
};

} // namespace

Result<std::vector<HidDeviceInfo>> enumerate_hid_devices() {
    const std::lock_guard lock(bus_mutex());
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
    const std::lock_guard lock(bus_mutex());
    if (auto ok = init_once(); !ok) return std::move(ok).error();
    hid_device* device = hid_open_path(path.c_str());
    if (!device) return make_error(ErrorCode::device_error, path + ": cannot be opened (permissions? see docs/haptics.md, 'Checking it')");
    return std::unique_ptr<HidTransport>(std::make_unique<HidapiTransport>(device, path));
}

} // namespace ikebana::devices
