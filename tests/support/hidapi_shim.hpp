#pragma once
// A stand-in for hidapi under the real HidapiTransport (engine/devices/hid_transport.hpp's HidApi): one
// ShimDevice is one open handle. It fails the test's checks, rather than crashing as hidapi 0.13 can,
// when two calls on the handle overlap, when a call comes from a thread other than the first caller's,
// or when a call comes after the close. It can act as a DIY force-feedback device at rest (a state
// report every millisecond of wall time), refuse reads or writes (unplugged), corrupt its reports, and
// hold a write (a stalled hub). It keeps every report it was written, in order.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include <pthread.h>
#include <sched.h>

#include "engine/core/monotonic_clock.hpp"
#include "engine/devices/diy_protocol.hpp"
#include "engine/devices/hid_transport.hpp"

namespace ikebana::test {

struct ShimDevice {
    // What it does.
    std::atomic<bool> sends_diy_reports{true}; // a DIY state report every millisecond
    std::atomic<bool> corrupt_reports{false};  // ... whose CRC is wrong
    std::atomic<bool> reads_fail{false};       // unplugged, as a read sees it
    std::atomic<bool> writes_fail{false};      // unplugged, as a write sees it
    std::atomic<bool> hold_writes{false};      // a write waits while this is true
    std::chrono::microseconds call_takes{20};  // each call lasts this long: room for an overlap to show

    // What it saw.
    std::atomic<bool> overlapped{false};
    std::atomic<bool> foreign_thread{false};
    std::atomic<bool> used_after_close{false};
    std::atomic<bool> closed{false};
    std::atomic<int> calls_in_progress{0};
    std::atomic<std::thread::id> owner{};
    std::atomic<int> writer_policy{-1};
    std::atomic<int> writer_priority{-1};
    std::atomic<std::uint64_t> writes_attempted{0};

    [[nodiscard]] std::vector<std::vector<std::uint8_t>> written() const {
        const std::lock_guard lock(mutex_);
        return written_;
    }
    // The force of the last report written (a DIY force report), or nullopt-like false.
    [[nodiscard]] bool last_force(glm::dvec3& out) const {
        const std::lock_guard lock(mutex_);
        if (written_.empty()) return false;
        const auto f = devices::diy::decode_force(written_.back());
        if (!f) return false;
        out = f->force_n;
        return true;
    }
    [[nodiscard]] bool problems() const { return overlapped || foreign_thread || used_after_close; }

    // HidApi's functions.
    static int read(void* handle, unsigned char* data, std::size_t length, int) {
        auto& d = *static_cast<ShimDevice*>(handle);
        const Call call(d);
        if (d.reads_fail) return -1;
        if (!d.sends_diy_reports) return 0;
        const std::int64_t now = monotonic_ns();
        if (now < d.next_report_ns_ || length < devices::diy::report_size) return 0;
        d.next_report_ns_ = std::max(d.next_report_ns_ + 1'000'000, now);
        devices::diy::StateReport r{};
        r.sequence = ++d.sequence_;
        r.status = devices::diy::status::motors_enabled;
        r.max_force_n = 3.0;
        auto bytes = devices::diy::encode_state(r);
        if (d.corrupt_reports) bytes.back() ^= 0xff;
        std::memcpy(data, bytes.data(), bytes.size());
        return static_cast<int>(bytes.size());
    }
    static int write(void* handle, const unsigned char* data, std::size_t length) {
        auto& d = *static_cast<ShimDevice*>(handle);
        const Call call(d);
        sched_param param{};
        int policy = -1;
        pthread_getschedparam(pthread_self(), &policy, &param);
        d.writer_policy = policy;
        d.writer_priority = param.sched_priority;
        while (d.hold_writes) std::this_thread::sleep_for(std::chrono::microseconds(200));
        ++d.writes_attempted;
        {
            const std::lock_guard lock(d.mutex_);
            d.written_.emplace_back(data, data + length); // failed ones too: what was last put on the wire
        }
        return d.writes_fail ? -1 : static_cast<int>(length);
    }
    static void close(void* handle) {
        auto& d = *static_cast<ShimDevice*>(handle);
        const Call call(d);
        d.closed = true;
    }
    static const devices::HidApi& api() {
        static const devices::HidApi a{&ShimDevice::read, &ShimDevice::write, &ShimDevice::close};
        return a;
    }

private:
    // One call on the handle: checks who makes it and that no other is in progress.
    class Call {
    public:
        explicit Call(ShimDevice& d) : d_(d) {
            if (d_.calls_in_progress.fetch_add(1) != 0) d_.overlapped = true;
            std::thread::id expected{};
            const auto me = std::this_thread::get_id();
            if (!d_.owner.compare_exchange_strong(expected, me) && expected != me) d_.foreign_thread = true;
            if (d_.closed) d_.used_after_close = true;
            std::this_thread::sleep_for(d_.call_takes);
        }
        ~Call() { d_.calls_in_progress.fetch_sub(1); }
        Call(const Call&) = delete;
        Call& operator=(const Call&) = delete;

    private:
        ShimDevice& d_;
    };

    mutable std::mutex mutex_;
    std::vector<std::vector<std::uint8_t>> written_;
    std::int64_t next_report_ns_ = 0;
    std::uint16_t sequence_ = 0;
};

} // namespace ikebana::test
