// The real HID transport (HidapiTransport), driven through a shim of the hidapi calls it makes: one
// thread owns each handle, the last report queued reaches the wire before the close, a write stuck
// past the close's wait is said, and the chain's every way of ending leaves a zero as the last report.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "engine/core/emergency_stop.hpp"
#include "engine/devices/emulated_diy.hpp"
#include "engine/devices/hid_devices.hpp"
#include "engine/devices/hid_transport.hpp"
#include "engine/devices/reconnecting_device.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "tests/support/hidapi_shim.hpp"

using namespace ikebana;
using namespace ikebana::devices;
using ikebana::test::ShimDevice;

namespace {

std::array<std::uint8_t, diy::report_size> force_report(std::uint16_t sequence, double fz) {
    return diy::encode_force(diy::ForceReport{sequence, glm::dvec3{0.0, 0.0, fz}, true, 2});
}

// Waits (bounded) until `done` says so.
template <typename F>
bool eventually(F done, std::chrono::milliseconds within = std::chrono::milliseconds(2000)) {
    const auto until = std::chrono::steady_clock::now() + within;
    while (!done()) {
        if (std::chrono::steady_clock::now() > until) return false;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    return true;
}

HidTransportOptions quiet(std::vector<std::string>* said = nullptr) {
    HidTransportOptions o;
    o.say = [said](std::string_view line) {
        if (said) said->emplace_back(line);
    };
    return o;
}

} // namespace

TEST(HidapiTransport, ReadsWritesAndTheCloseOfAHandleAllComeFromOneThreadOfItsOwnNeverTwoAtOnce) {
    ShimDevice shim;
    {
        auto transport = make_hidapi_transport(ShimDevice::api(), &shim, "shim", quiet());
        // The 1 kHz loop reads and writes; a watchdog thread writes zeros meanwhile, as in the app.
        std::atomic<bool> done{false};
        std::thread watchdog([&] {
            while (!done) {
                (void)transport->write(force_report(0, 0.0));
                std::this_thread::sleep_for(std::chrono::microseconds(300));
            }
        });
        std::array<std::uint8_t, 64> buffer{};
        std::size_t reports = 0;
        for (int tick = 0; tick < 300; ++tick) {
            auto n = transport->read(buffer, 0);
            ASSERT_TRUE(n);
            if (*n > 0) ++reports;
            ASSERT_TRUE(transport->write(force_report(static_cast<std::uint16_t>(tick + 1), 0.5)));
            std::this_thread::sleep_for(std::chrono::microseconds(1000));
        }
        done = true;
        watchdog.join();
        EXPECT_GT(reports, 100u) << "the reports the I/O thread read reach the caller";
    }
    EXPECT_TRUE(shim.closed);
    EXPECT_FALSE(shim.overlapped) << "two hidapi calls on one handle at once";
    EXPECT_FALSE(shim.foreign_thread) << "a call from a thread that does not own the handle";
    EXPECT_FALSE(shim.used_after_close);
    EXPECT_NE(shim.owner.load(), std::this_thread::get_id()) << "the caller's thread never calls hidapi";
}

TEST(HidapiTransport, TheLastReportQueuedBeforeTheTransportGoesIsWrittenBeforeTheHandleCloses) {
    for (int round = 0; round < 20; ++round) {
        ShimDevice shim;
        {
            auto transport = make_hidapi_transport(ShimDevice::api(), &shim, "shim", quiet());
            for (int i = 1; i <= 5; ++i) ASSERT_TRUE(transport->write(force_report(static_cast<std::uint16_t>(i), 2.0)));
            ASSERT_TRUE(transport->write(force_report(6, 0.0)));
        } // destroyed straight after: the zero is still in the mailbox
        glm::dvec3 last{1.0};
        ASSERT_TRUE(shim.last_force(last)) << "round " << round;
        EXPECT_EQ(last, glm::dvec3(0.0)) << "round " << round << ": the last report on the wire is the zero queued last";
        EXPECT_TRUE(shim.closed);
        EXPECT_FALSE(shim.problems());
    }
}

TEST(HidapiTransport, AWriteStuckPastTheClosesWaitIsSaidAndTheHandleIsClosedOnceItReturns) {
    ShimDevice shim;
    std::vector<std::string> said;
    shim.hold_writes = true;
    auto options = quiet(&said);
    options.close_wait = std::chrono::milliseconds(50);
    auto transport = make_hidapi_transport(ShimDevice::api(), &shim, "stalled hub", options);
    ASSERT_TRUE(transport->write(force_report(1, 1.0)));
    ASSERT_TRUE(eventually([&] { return shim.calls_in_progress.load() > 0; }));
    const auto before = std::chrono::steady_clock::now();
    transport.reset();
    const auto took = std::chrono::steady_clock::now() - before;
    EXPECT_LT(took, std::chrono::milliseconds(1000)) << "closing does not wait for a stuck write";
    ASSERT_EQ(said.size(), 1u);
    EXPECT_NE(said[0].find("stalled hub: the last report has waited for the device for over 50 ms"), std::string::npos) << said[0];
    EXPECT_FALSE(shim.closed) << "not closed under a write in progress";
    shim.hold_writes = false;
    EXPECT_TRUE(eventually([&] { return shim.closed.load(); })) << "closed by its own thread once the write returned";
    EXPECT_FALSE(shim.problems());
}

TEST(HidapiTransport, AFailedReadIsTheDeviceGoneAndAFailedWriteIsSaidAtTheNextWrite) {
    ShimDevice shim;
    auto transport = make_hidapi_transport(ShimDevice::api(), &shim, "shim", quiet());
    std::array<std::uint8_t, 64> buffer{};
    shim.reads_fail = true;
    EXPECT_TRUE(eventually([&] { return !transport->read(buffer, 0); })) << "unplugged: the read fails";
    const auto gone = transport->read(buffer, 0);
    ASSERT_FALSE(gone);
    EXPECT_EQ(gone.error().code, ErrorCode::device_error);
    EXPECT_EQ(gone.error().text(), "a read from the device failed (unplugged?)");
    shim.writes_fail = true;
    // Queued; said failed at this write or a following one (the I/O thread may have tried it before this
    // write looks at the flag: a loaded machine, TSan).
    (void)transport->write(force_report(1, 0.0));
    EXPECT_TRUE(eventually([&] { return shim.writes_attempted.load() >= 1; }));
    EXPECT_TRUE(eventually([&] { return !transport->write(force_report(2, 0.0)); })) << "the failure is reported at a following write";
}

TEST(HidapiTransport, ItsCountsSayWhichQueuedReportLastReachedTheDevice) {
    ShimDevice shim;
    auto transport = make_hidapi_transport(ShimDevice::api(), &shim, "shim", quiet());
    EXPECT_EQ(transport->wire().queued, 0u);
    ASSERT_TRUE(transport->write(force_report(1, 1.0)));
    ASSERT_TRUE(eventually([&] { return transport->wire().written == 1; }));
    shim.hold_writes = true;
    ASSERT_TRUE(transport->write(force_report(2, 2.0)));
    ASSERT_TRUE(eventually([&] { return shim.calls_in_progress.load() > 0 && shim.hold_writes; }));
    ASSERT_TRUE(transport->write(force_report(3, 3.0)));
    const WireCounts w = transport->wire();
    EXPECT_EQ(w.queued, 3u);
    EXPECT_LT(w.written, 3u) << "the third waits behind a stuck write";
    shim.hold_writes = false;
    EXPECT_TRUE(eventually([&] { return transport->wire().written == 3; }));
}

TEST(HidapiTransport, TwoWritersAtOnceNeverWaitForEachOtherAndNeitherSeesItsOwnReportsGoBackwards) {
    // The lane and the watchdog write at once: each takes a free mailbox, never a lock. Reports from
    // one writer reach the wire in the order it wrote them, and the last written is the last queued.
    ShimDevice shim;
    shim.call_takes = std::chrono::microseconds(0);
    shim.sends_diy_reports = false;
    {
        auto transport = make_hidapi_transport(ShimDevice::api(), &shim, "shim", quiet());
        auto writer = [&](double sign) {
            for (int i = 1; i <= 3000; ++i) ASSERT_TRUE(transport->write(force_report(static_cast<std::uint16_t>(i), sign * i * 1e-3)));
        };
        std::thread lane(writer, 1.0);
        std::thread watchdog(writer, -1.0);
        lane.join();
        watchdog.join();
        EXPECT_EQ(transport->wire().queued, 6000u);
        EXPECT_TRUE(eventually([&] { return transport->wire().written == 6000; })) << "the report queued last is written";
    }
    int last_lane = 0, last_watchdog = 0, lane_seen = 0, watchdog_seen = 0;
    for (const auto& bytes : shim.written()) {
        auto report = diy::decode_force(bytes);
        ASSERT_TRUE(report);
        const int value = static_cast<int>(std::lround(report->force_n.z * 1e3));
        int& last = value > 0 ? last_lane : last_watchdog;
        (value > 0 ? lane_seen : watchdog_seen) += 1;
        EXPECT_GT(std::abs(value), last) << "a writer's report went out after one it wrote later";
        last = std::abs(value);
    }
    EXPECT_GT(lane_seen, 0);
    EXPECT_GT(watchdog_seen, 0);
    EXPECT_TRUE(last_lane == 3000 || last_watchdog == 3000) << "the last report queued reached the wire";
    EXPECT_FALSE(shim.problems());
}

TEST(HidapiTransport, ItsThreadRunsAtTheRealTimePriorityAskedWhenPermittedAndSaysWhichItGot) {
    ShimDevice shim;
    HidTransportOptions options = quiet();
    options.fifo_priority = hid_io_fifo_priority;
    auto transport = make_hidapi_transport(ShimDevice::api(), &shim, "shim", options);
    ASSERT_TRUE(transport->write(force_report(1, 0.0)));
    ASSERT_TRUE(eventually([&] { return shim.writer_policy.load() != -1; }));
    if (transport->io_priority() == IoPriority::realtime) {
        EXPECT_EQ(shim.writer_policy.load(), SCHED_FIFO);
        EXPECT_EQ(shim.writer_priority.load(), haptic_lane_fifo_priority - 1) << "just below the haptic lane's";
    } else {
        EXPECT_EQ(transport->io_priority(), IoPriority::not_permitted);
        EXPECT_NE(shim.writer_policy.load(), SCHED_FIFO);
    }
    ShimDevice normal_shim;
    options.fifo_priority = 0;
    auto normal = make_hidapi_transport(ShimDevice::api(), &normal_shim, "shim", options);
    EXPECT_EQ(normal->io_priority(), IoPriority::normal);
}

// The chain's ends, through the real transport: whatever way it ends, the last report is a zero.
TEST(HidapiTransport, AForceChainDestroyedWhilePushingLeavesAZeroAsTheLastReportWritten) {
    ShimDevice shim;
    {
        auto chain = make_force_safe(std::make_unique<DiyForceDevice>(make_hidapi_transport(ShimDevice::api(), &shim, "shim", quiet())));
        std::int64_t now = 0;
        // Until it pushes: the ramp runs on the wall clock and starts again after a stall, so a loaded
        // machine (TSan, two tests at once) takes longer than 400 ticks to get there.
        for (int tick = 0; tick < 10'000 && !(tick >= 400 && glm::length(chain->last_sent().queued_n) > 0.5); ++tick) {
            (void)chain->poll(now += 1000);
            ASSERT_TRUE(chain->send_force({0.0, 0.0, 1.5}));
            std::this_thread::sleep_for(std::chrono::microseconds(1000));
        }
        ASSERT_GT(glm::length(chain->last_sent().queued_n), 0.5) << "it was pushing";
    }
    glm::dvec3 last{1.0};
    ASSERT_TRUE(shim.last_force(last));
    EXPECT_EQ(last, glm::dvec3(0.0));
    EXPECT_FALSE(shim.problems());
}

TEST(HidapiTransport, AForceChainThatLosesItsDeviceLeavesAZeroAsTheLastReportItWasWritten) {
    // Reopened devices are new shims; the one that failed must have been left with a zero.
    std::vector<std::unique_ptr<ShimDevice>> shims;
    std::mutex shims_mutex;
    ShimDevice* first = nullptr;
    {
        auto reconnecting = std::make_unique<ReconnectingDevice>(
            [&]() -> Result<std::unique_ptr<HapticDevice>> {
                const std::lock_guard lock(shims_mutex);
                shims.push_back(std::make_unique<ShimDevice>());
                return std::unique_ptr<HapticDevice>(std::make_unique<DiyForceDevice>(make_hidapi_transport(ShimDevice::api(), shims.back().get(), "shim", quiet())));
            },
            DeviceCapabilities{.name = "DIY", .has_force_output = true, .max_force_n = 3.0, .silent_after_us = 20'000}, 1000);
        auto chain = make_force_safe(std::move(reconnecting));
        auto* safe = dynamic_cast<SafeForceDevice*>(chain.get());
        ASSERT_NE(safe, nullptr);
        std::int64_t now = 0;
        bool pushed = false;
        for (int tick = 0; tick < 3000 && !safe->lost(); ++tick) {
            (void)chain->poll(now += 1000);
            (void)chain->send_force({0.0, 0.0, 1.5});
            if (!pushed && glm::length(chain->last_sent().queued_n) > 1.0) {
                pushed = true;
                const std::lock_guard lock(shims_mutex);
                first = shims.front().get();
                first->writes_fail = true; // pulled out mid-push
            }
            std::this_thread::sleep_for(std::chrono::microseconds(1000));
        }
        ASSERT_TRUE(pushed);
        EXPECT_TRUE(safe->lost());
        // The lost device is closed on the opener's thread, not this one.
        EXPECT_TRUE(eventually([&] { return first->closed.load(); }));
    }
    ASSERT_NE(first, nullptr);
    glm::dvec3 last{1.0};
    ASSERT_TRUE(first->last_force(last));
    EXPECT_EQ(last, glm::dvec3(0.0)) << "the last report put on the wire (its write failed or not) is a zero";
    const std::lock_guard lock(shims_mutex);
    for (const auto& s : shims) EXPECT_FALSE(s->problems());
}

// What the HUD calls "feels" is the force of the last report the device was written; what the chain
// queued behind a stuck write is said beside it.
TEST(HidapiTransport, TheChainSaysTheForceOnTheWireAndTheOneQueuedBehindAStuckWrite) {
    ShimDevice shim;
    auto chain = make_force_safe(std::make_unique<DiyForceDevice>(make_hidapi_transport(ShimDevice::api(), &shim, "shim", quiet())));
    std::int64_t now = 0;
    const auto tick = [&](double fz) {
        (void)chain->poll(now += 1000);
        (void)chain->send_force({0.0, 0.0, fz});
        std::this_thread::sleep_for(std::chrono::microseconds(1000));
    };
    for (int i = 0; i < 100; ++i) tick(0.0);   // engaged
    for (int i = 0; i < 800; ++i) tick(1.0);   // ramped up to the 1 N asked
    ASSERT_TRUE(eventually([&] { return std::abs(chain->last_sent().sent_n.z - 1.0) < 1e-9; }))
        << "written: on the wire; sent " << chain->last_sent().sent_n.z << " queued " << chain->last_sent().queued_n.z << " written " << chain->wire().written << " of " << chain->wire().queued;
    shim.hold_writes = true;                    // the hub stalls
    for (int i = 0; i < 10; ++i) tick(2.0);    // 10 ms: short of the 20 ms after which a stuck write counts as failed
    const SentForce stuck = chain->last_sent();
    EXPECT_NEAR(stuck.queued_n.z, 2.0, 1e-9) << "the chain let out 2 N";
    EXPECT_LT(stuck.sent_n.z, 1.1) << "but the device has not been written more than about 1 N";
    shim.hold_writes = false;
    EXPECT_TRUE(eventually([&] {
        tick(2.0);
        return std::abs(chain->last_sent().sent_n.z - 2.0) < 1e-9;
    })) << "written once the hub moves again";
}

// std::terminate with a device pushing: the handler zeroes it, waits for the zero to reach the wire,
// says why the program ended and aborts. The emulated DIY device (behind the real transport) logs what
// it is written to a file the parent reads after the child has died.
TEST(HidapiTransportDeathTest, StdTerminateZeroesEveryPushingDeviceBeforeTheProgramEnds) {
    const std::string log = ::testing::TempDir() + "terminate_forces.log";
    std::remove(log.c_str());
    EXPECT_DEATH(
        {
            install_terminate_handler();
            auto transport = open_emulated_diy(log);
            if (!transport) std::abort();
            auto chain = make_force_safe(std::make_unique<DiyForceDevice>(std::move(transport).value()));
            std::int64_t now = 0;
            // Pressing, until the chain has engaged and pushes (about 2 s of the emulated hand).
            for (int tick = 0; tick < 3000 && glm::length(chain->last_sent().sent_n) < 1.0; ++tick) {
                (void)chain->poll(now += 1000);
                (void)chain->send_force({0.0, 0.0, tick < 300 ? 0.0 : 2.0});
                std::this_thread::sleep_for(std::chrono::microseconds(1000));
            }
            std::terminate();
        },
        "ikebana: ended by std::terminate \\(no exception\\); 1 pushing device\\(s\\) sent zero force");
    std::ifstream in(log);
    std::string line;
    std::string last;
    bool pushed = false;
    while (std::getline(in, line)) {
        if (line != "force 0.000000 0.000000 0.000000") pushed = true;
        last = line;
    }
    EXPECT_TRUE(pushed) << "the device was pushed on before the end";
    EXPECT_EQ(last, "force 0.000000 0.000000 0.000000");
}
