#include <gtest/gtest.h>

#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/devices/hid_devices.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "tests/support/fake_transport.hpp"

using namespace ikebana;
using namespace ikebana::devices;

namespace {
using ikebana::test::FakeTransport;

std::vector<std::uint8_t> state(std::uint16_t seq, glm::ivec3 position_um, std::uint16_t buttons, double max_force = 2.5) {
    const auto b = diy::encode_state(diy::StateReport{seq, 0, position_um, {0, 0, 0}, buttons, diy::status::motors_enabled, max_force});
    return {b.begin(), b.end()};
}
} // namespace

TEST(HidDevices, ProfilesAreMatchedByVendorAndProduct) {
    EXPECT_EQ(match_hid_device({0x046d, 0xc626, "", "", ""}).kind, DeviceMatch::Kind::spacemouse);
    EXPECT_EQ(match_hid_device({diy_vendor_id, diy_product_id, "", "", ""}).kind, DeviceMatch::Kind::diy_force);
    EXPECT_EQ(match_hid_device({0x1234, 0x5678, "", "", ""}).kind, DeviceMatch::Kind::unknown);
}

TEST(HidDevices, SpaceMouseSkipsGarbageAndReportsUnplugging) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    fake->inbound = {{0x01, 0x5e, 0x01, 0, 0, 0, 0}, {0x01, 0xde, 0xad}, {0x99, 1, 2, 3}, {0x03, 0x01}};
    SpaceMouseDevice device(std::move(transport), *find_spacemouse_profile(0x046d, 0xc626));
    const auto s = device.poll(10);
    ASSERT_TRUE(s);
    EXPECT_DOUBLE_EQ(s->position.x, 1.0);
    EXPECT_EQ(s->buttons, 1u);
    EXPECT_EQ(device.parser().reports_refused(), 1u);
    EXPECT_FALSE(device.capabilities().has_force_output);
    fake->unplugged = true;
    EXPECT_FALSE(device.poll(20)) << "unplugging is reported, not hidden";
}

TEST(HidDevices, DiyDeviceReadsPositionAndRefusesCorruptAndReplayedReports) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    auto corrupt = state(2, {9, 9, 9}, 0);
    corrupt[10] ^= 0xff;
    fake->inbound = {state(1, {10000, -20000, 30000}, 1), corrupt, state(1, {5, 5, 5}, 0)};
    DiyForceDevice device(std::move(transport));
    const auto s = device.poll(1000);
    ASSERT_TRUE(s);
    EXPECT_NEAR(s->position.x, 0.01, 1e-12);
    EXPECT_NEAR(s->position.y, -0.02, 1e-12);
    EXPECT_EQ(s->buttons, 1u);
    EXPECT_EQ(device.reports_refused(), 2u) << "the corrupt one and the replay";
    EXPECT_DOUBLE_EQ(device.max_force_now_n(), 2.5) << "the device's own limit tightens ours";
    EXPECT_DOUBLE_EQ(device.capabilities().max_force_n, 3.0) << "capabilities stay as made: other threads read them while it polls";
}

// The DIY device's reported limit tightens while other threads read what it can do (the watchdog's
// owner, the HUD): its capabilities never change once made (under ThreadSanitizer this was a race on
// caps_.max_force_n), and the limit now is an atomic.
TEST(HidDevices, ADiyDevicesLimitTightensWhileOtherThreadsReadItsCapabilities) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    DiyForceDevice device(std::move(transport));
    std::atomic<bool> done{false};
    std::atomic<int> wrong{0};
    std::thread reader([&] {
        while (!done) {
            if (device.capabilities().max_force_n != 3.0) ++wrong;
            const double now = device.max_force_now_n();
            if (now > 3.0 || now < 1.0) ++wrong;
        }
    });
    std::uint16_t seq = 0;
    for (int tick = 0; tick < 500; ++tick) {
        {
            const std::lock_guard lock(fake->mutex);
            fake->inbound.push_back(state(++seq, {0, 0, 0}, 0, 3.0 - 0.002 * tick));
        }
        ASSERT_TRUE(device.poll(tick * 1000));
    }
    done = true;
    reader.join();
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_NEAR(device.max_force_now_n(), 2.0, 0.05);
}

TEST(HidDevices, DiyDeviceNeverSendsMoreThanItsLimitNorNaN) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    fake->inbound = {state(1, {0, 0, 0}, 0, 2.5)};
    DiyForceDevice device(std::move(transport));
    std::uint16_t previous_sequence = 0;
    for (int tick = 1; tick <= 2000; ++tick) {
        ASSERT_TRUE(device.poll(tick * 1000));
        const glm::dvec3 request = tick % 97 == 0 ? glm::dvec3{std::nan(""), 0, 0} : glm::dvec3{0, 0, 100.0};
        ASSERT_TRUE(device.send_force(request));
        const auto report = diy::decode_force(fake->written.back());
        ASSERT_TRUE(report);
        ASSERT_LE(glm::length(report->force_n), 2.5 + 1e-3) << "tick " << tick;
        ASSERT_TRUE(std::isfinite(report->force_n.z));
        ASSERT_EQ(static_cast<std::uint16_t>(report->sequence - previous_sequence), 1) << "one new sequence per report";
        previous_sequence = report->sequence;
    }
}

// The force watchdog writes zero from its own thread while the haptic loop writes forces.
TEST(HidDevices, WatchdogZeroFromAnotherThreadIsSafe) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    DiyForceDevice device(std::move(transport));
    std::thread watchdog([&] {
        for (int i = 0; i < 500; ++i) (void)device.send_zero();
    });
    for (int tick = 1; tick <= 500; ++tick) {
        (void)device.poll(tick * 1000);
        (void)device.send_force({0, 0, 1.0});
    }
    watchdog.join();
    std::lock_guard lock(fake->mutex);
    EXPECT_EQ(fake->written.size(), 1000u);
    for (const auto& w : fake->written) EXPECT_TRUE(diy::decode_force(w));
}

// The watchdog's zero goes through the generic interface, even across a reconnecting wrapper.
TEST(HidDevices, ZeroForceReachesTheDeviceThroughTheInterface) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    std::unique_ptr<HapticDevice> device = std::make_unique<DiyForceDevice>(std::move(transport));
    ASSERT_TRUE(device->zero_force());
    ASSERT_EQ(fake->written.size(), 1u);
    const auto report = diy::decode_force(fake->written[0]);
    ASSERT_TRUE(report);
    EXPECT_EQ(report->force_n, glm::dvec3(0.0));
}

// A DIY device that stays plugged in but stops reporting (a firmware hang, a stalled hub) used to hand
// back its last report stamped with the current time, so the host pushed on against a frozen position.
// Its samples now carry the time their report arrived, and behind the safety chain it is silent after
// 20 ms: the poll fails (the hand lets go) and the force fades; when reports resume it answers again.
TEST(HidDevices, AStaleDiyDeviceSaysHowOldItsReportIsAndFallsSilent) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    std::int64_t now = 0;
    SafeForceDevice device(std::make_unique<DiyForceDevice>(std::move(transport)), ForceSafetyConfig{}, [&now] { return now; });
    std::uint16_t seq = 0;
    const auto report = [&] {
        const std::lock_guard lock(fake->mutex);
        fake->inbound.push_back(state(++seq, {1000, 0, 0}, 0));
    };
    for (int tick = 0; tick < 100; ++tick) {
        report();
        const auto s = device.poll(now += 1000);
        ASSERT_TRUE(s);
        EXPECT_EQ(s->report_us, now);
        (void)device.send_force({0.0, 0.0, 0.1});
    }
    const std::int64_t last_report = now;
    // Hung: nothing more arrives.
    for (int tick = 1; tick <= 20; ++tick) {
        const auto s = device.poll(now += 1000);
        ASSERT_TRUE(s) << tick;
        EXPECT_EQ(s->report_us, last_report) << "the sample keeps its report's time";
    }
    const auto silent = device.poll(now += 1000);
    ASSERT_FALSE(silent);
    EXPECT_EQ(silent.error().code, ErrorCode::device_silent);
    EXPECT_EQ(silent.error().text(), "the device has sent nothing for longer than its profile allows");
    EXPECT_TRUE(silent.error().message.empty()) << "made on the 1 kHz thread: no words that allocate";
    report();
    EXPECT_TRUE(device.poll(now += 1000)) << "reports again: it answers again";
}
