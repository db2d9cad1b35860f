#pragma once
// A HID transport for tests: replays fixture reports and records what is written, as hidapi would move
// them (this machine has no USB and no /dev/uhid). Thread-safe, so a watchdog thread may write too.
#include <algorithm>
#include <deque>
#include <mutex>
#include <vector>

#include "engine/devices/hid_transport.hpp"

namespace ikebana::test {

struct FakeTransport : devices::HidTransport {
    std::deque<std::vector<std::uint8_t>> inbound;
    std::vector<std::vector<std::uint8_t>> written;
    std::mutex mutex;
    bool unplugged = false;

    Result<std::size_t> read(std::span<std::uint8_t> buffer, int) override {
        std::lock_guard lock(mutex);
        if (unplugged) return make_error(ErrorCode::device_error, "fake: gone");
        if (inbound.empty()) return std::size_t{0};
        const auto report = inbound.front();
        inbound.pop_front();
        const std::size_t n = std::min(report.size(), buffer.size());
        std::copy_n(report.begin(), n, buffer.begin());
        return n;
    }
    Result<void> write(std::span<const std::uint8_t> report) override {
        std::lock_guard lock(mutex);
        if (unplugged) return make_error(ErrorCode::device_error, "fake: gone");
        written.emplace_back(report.begin(), report.end());
        return {};
    }
};

} // namespace ikebana::test
