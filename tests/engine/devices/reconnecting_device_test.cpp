#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "engine/devices/reconnecting_device.hpp"

using namespace ikebana;
using namespace ikebana::devices;

namespace {
// A device that answers until `plugged` goes false.
struct Plug {
    bool plugged = true;
    int opens = 0;
};
struct PlugDevice : HapticDevice {
    Plug& plug;
    DeviceCapabilities caps{"plug", true, 3.0, glm::dvec3{0.1}, true};
    explicit PlugDevice(Plug& p) : plug(p) {}
    const DeviceCapabilities& capabilities() const override { return caps; }
    Result<DeviceSample> poll(std::int64_t now) override {
        if (!plug.plugged) return make_error(ErrorCode::device_error, "read failed");
        DeviceSample s;
        s.time_us = now;
        return s;
    }
    Result<void> send_force(glm::dvec3) override {
        if (!plug.plugged) return make_error(ErrorCode::device_error, "write failed");
        return {};
    }
};
} // namespace

namespace {
// Polls as a 1 kHz loop would until `until` holds or 10 s have passed; the time polls took at most.
template <typename Until>
std::int64_t poll_until(ReconnectingDevice& device, std::int64_t& now, Until until) {
    std::int64_t slowest_us = 0;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!until() && std::chrono::steady_clock::now() < give_up) {
        const auto before = std::chrono::steady_clock::now();
        (void)device.poll(now += 1000);
        slowest_us = std::max<std::int64_t>(slowest_us, std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - before).count());
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return slowest_us;
}
} // namespace

TEST(ReconnectingDevice, DropsAnUnpluggedDeviceAndReopensItWhenItIsBack) {
    Plug plug;
    std::atomic<bool> plugged{true};
    std::atomic<int> opens{0};
    ReconnectingDevice device(
        [&]() -> Result<std::unique_ptr<HapticDevice>> {
            ++opens;
            if (!plugged.load()) return make_error(ErrorCode::device_error, "no such device");
            return std::unique_ptr<HapticDevice>(std::make_unique<PlugDevice>(plug));
        },
        DeviceCapabilities{"plug", true, 3.0, glm::dvec3{0.1}, true}, 20'000);
    std::int64_t now = 0;
    (void)poll_until(device, now, [&] { return device.attached(); });
    ASSERT_TRUE(device.attached());
    EXPECT_EQ(opens.load(), 1);
    plug.plugged = false;
    plugged.store(false);
    EXPECT_FALSE(device.poll(now += 1000)) << "the unplugging is reported";
    EXPECT_FALSE(device.attached());
    EXPECT_TRUE(device.send_force({0, 0, 1})) << "forces go nowhere, without error, while unplugged";
    // Tried again every 20 ms on the device's own thread while it is away.
    (void)poll_until(device, now, [&] { return opens.load() >= 4; });
    EXPECT_GE(opens.load(), 4);
    EXPECT_FALSE(device.attached());
    plug.plugged = true;
    plugged.store(true);
    (void)poll_until(device, now, [&] { return device.attached(); });
    EXPECT_TRUE(device.attached()) << "re-attached";
    EXPECT_EQ(device.reconnects(), 1u);
    EXPECT_TRUE(device.poll(now += 1000));
}

// Opening a HID device enumerates the bus and opens a file: on a stalled hub, hundreds of milliseconds.
// It used to happen inside poll(), on the 1 kHz thread. Now an opener that blocks for 300 ms holds no
// poll up: each returns at once, "disconnected", until the device is there.
TEST(ReconnectingDevice, AnOpenerThatBlocksNeverHoldsThePollingThread) {
    Plug plug;
    std::atomic<int> opens{0};
    ReconnectingDevice device(
        [&]() -> Result<std::unique_ptr<HapticDevice>> {
            ++opens;
            std::this_thread::sleep_for(std::chrono::milliseconds(300));
            return std::unique_ptr<HapticDevice>(std::make_unique<PlugDevice>(plug));
        },
        DeviceCapabilities{"plug", true, 3.0, glm::dvec3{0.1}, true}, 500'000);
    std::int64_t now = 0;
    const auto first = device.poll(now += 1000);
    ASSERT_FALSE(first) << "not there yet: the opener is still at work";
    EXPECT_EQ(first.error().text(), "disconnected");
    const std::int64_t slowest_us = poll_until(device, now, [&] { return device.attached(); });
    EXPECT_TRUE(device.attached());
    // Far from the opener's 300 ms (a sanitizer build on a busy machine may take a millisecond or two).
    EXPECT_LT(slowest_us, 50'000) << "a poll waited for the opener";
    EXPECT_GE(now, 100'000) << "the polls went on meanwhile, 1 ms apart";
    EXPECT_EQ(opens.load(), 1);
}

namespace {
// A device that says which thread destroyed it, and whose limit it reports goes down as it is polled.
struct Witness : HapticDevice {
    DeviceCapabilities caps{"witness", true, 3.0, glm::dvec3{0.1}, true};
    std::atomic<std::thread::id>* destroyed_on;
    std::atomic<double> limit{3.0};
    explicit Witness(std::atomic<std::thread::id>* d) : destroyed_on(d) {}
    ~Witness() override {
        if (destroyed_on) *destroyed_on = std::this_thread::get_id();
    }
    const DeviceCapabilities& capabilities() const override { return caps; }
    double max_force_now_n() const override { return limit.load(); }
    Result<DeviceSample> poll(std::int64_t now) override {
        limit = 2.0;
        DeviceSample s;
        s.time_us = now;
        return s;
    }
    Result<void> send_force(glm::dvec3) override { return {}; }
};
} // namespace

// Dropped again and again, as fast as the opener hands devices over: none is ever closed on the
// caller's (the 1 kHz) thread, however late the opener thread gets round to the ones dropped before.
// The caller's slot for them used to be one pointer, which a late opener left full: the caller then
// deleted the device in it itself (hid_close and a thread's join, on the 1 kHz thread).
TEST(ReconnectingDevice, ADeviceDroppedBeforeTheOpenerClosedTheLastIsNeverClosedOnTheCallersThread) {
    std::atomic<std::thread::id> last_destroyed_on{};
    std::atomic<int> destroyed_here{0};
    std::atomic<int> opened{0};
    const auto caller = std::this_thread::get_id();
    {
        ReconnectingDevice device(
            [&]() -> Result<std::unique_ptr<HapticDevice>> {
                ++opened;
                return std::unique_ptr<HapticDevice>(std::make_unique<Witness>(&last_destroyed_on));
            },
            DeviceCapabilities{"witness", true, 3.0, glm::dvec3{0.1}, true}, 1000);
        std::int64_t now = 0;
        int drops = 0;
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (drops < 60 && std::chrono::steady_clock::now() < give_up) {
            if (device.poll(now += 1000) && device.drop()) ++drops;
            if (last_destroyed_on.exchange(std::thread::id{}) == caller) ++destroyed_here;
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        EXPECT_EQ(drops, 60);
        EXPECT_EQ(destroyed_here.load(), 0) << "a dropped device was closed on the caller's thread";
    }
    EXPECT_GE(opened.load(), 60);
}

// Another thread (the HUD's, the watchdog owner's) holds the capabilities while the device is dropped,
// closed and reopened: they are the reconnecting device's own, never a reference into a device the
// opener thread may delete; the limit the device reports later comes through max_force_now_n.
TEST(ReconnectingDevice, ItsCapabilitiesStayValidForOtherThreadsWhileItsDeviceIsSwappedAndDeleted) {
    ReconnectingDevice device([]() -> Result<std::unique_ptr<HapticDevice>> { return std::unique_ptr<HapticDevice>(std::make_unique<Witness>(nullptr)); },
                              DeviceCapabilities{"expected", true, 3.0, glm::dvec3{0.1}, true}, 1000);
    const DeviceCapabilities& held = device.capabilities();
    std::atomic<bool> done{false};
    std::atomic<int> wrong{0};
    std::thread reader([&] {
        while (!done) {
            if (held.name != "expected" || device.capabilities().max_force_n != 3.0) ++wrong;
            const double limit = device.max_force_now_n();
            if (limit != 3.0 && limit != 2.0) ++wrong;
        }
    });
    std::int64_t now = 0;
    for (int i = 0; i < 2000; ++i) {
        if (device.poll(now += 1000) && i % 10 == 0) (void)device.drop();
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    done = true;
    reader.join();
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_EQ(&device.capabilities(), &held) << "one object for the device's life";
}
