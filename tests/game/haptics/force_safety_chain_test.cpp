#include <gtest/gtest.h>

#include <chrono>
#include <deque>
#include <thread>
#include <functional>
#include <mutex>

#include "components/hand.hpp"
#include "engine/devices/diy_protocol.hpp"
#include "engine/devices/hid_devices.hpp"
#include "engine/devices/reconnecting_device.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "engine/devices/woodenhaptics.hpp"
#include "engine/sched/clocks.hpp"
#include "game/devices/hand_device_selection.hpp"
#include "game/scene/scene.hpp"
#include "game/world/world.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "scripted_hands.hpp"
#include "tests/support/fake_transport.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {

// A force device of no particular backend, held 5 cm under the table top (its hand presses down).
struct Probe final : devices::HapticDevice {
    std::vector<glm::dvec3>& sent;
    devices::DeviceCapabilities caps{"probe", true, 10.0, glm::dvec3{0.1}, true};
    double height_m = -0.05;
    const double* follow_m = nullptr; // set: its height is read from here at each poll
    explicit Probe(std::vector<glm::dvec3>& s) : sent(s) {}
    const devices::DeviceCapabilities& capabilities() const override { return caps; }
    Result<devices::DeviceSample> poll(std::int64_t now_us) override {
        devices::DeviceSample s;
        s.time_us = now_us;
        s.position = {0.3, 0.3, follow_m ? *follow_m : height_m};
        return s;
    }
    Result<void> send_force(glm::dvec3 f) override {
        sent.push_back(f);
        return {};
    }
};

std::unique_ptr<World> world_with_one_hand() {
    SceneDef scene = test::kenzan_bench();
    scene.hands.push_back({0, {0.3, 0.3, 0.1}, 0.02, ""});
    return test::world_of(scene);
}

// Where the probes of the wrapping test hold their handles (they read it at each poll).
double probe_height_m = -0.05;

struct Backend {
    std::string name;
    // Makes the device and says how to read back the forces that reached its wire, in newtons.
    std::function<std::unique_ptr<devices::HapticDevice>(std::function<std::vector<glm::dvec3>()>&)> make;
};

} // namespace

// Whichever backend a hand gets, the force on its wire went through the one safety layer. The devices
// of no particular backend are held above the table until the chain engages (on the wall clock: at
// about real time) and then pressed 5 cm into it: the hand asks 20 N and more, the wire rises from
// zero to 3 N and no further. The HID backends report no position here (no reports are fed), so their hand
// sits in the table from the start and their wires carry what the chain lets through while it waits:
// the check there is that every byte on the wire decodes to a force within the limit.
TEST(ForceSafety, WrapsEveryForceDevice) {
    std::vector<Backend> backends;
    backends.push_back({"any force device", [](auto& wire) {
                            auto sent = std::make_shared<std::vector<glm::dvec3>>();
                            wire = [sent] { return *sent; };
                            auto probe = std::make_unique<Probe>(*sent);
                            probe->follow_m = &probe_height_m;
                            return std::unique_ptr<devices::HapticDevice>(std::move(probe));
                        }});
    backends.push_back({"DIY over HID", [](auto& wire) {
                            auto transport = std::make_unique<test::FakeTransport>();
                            auto* fake = transport.get(); // lives as long as the world that owns the device
                            wire = [fake] {
                                std::vector<glm::dvec3> f;
                                for (const auto& b : fake->written) f.push_back(devices::diy::decode_force(b)->force_n);
                                return f;
                            };
                            auto device = std::make_unique<devices::DiyForceDevice>(std::move(transport), 10.0);
                            return std::unique_ptr<devices::HapticDevice>(std::move(device));
                        }});
    backends.push_back({"a reconnecting wrapper", [](auto& wire) {
                            auto sent = std::make_shared<std::vector<glm::dvec3>>();
                            wire = [sent] { return *sent; };
                            return std::unique_ptr<devices::HapticDevice>(std::make_unique<devices::ReconnectingDevice>(
                                [sent]() -> Result<std::unique_ptr<devices::HapticDevice>> {
                                    auto probe = std::make_unique<Probe>(*sent);
                                    probe->follow_m = &probe_height_m;
                                    return std::unique_ptr<devices::HapticDevice>(std::move(probe));
                                },
                                devices::DeviceCapabilities{"probe", true, 10.0, glm::dvec3{0.1}, true}, 0));
                        }});
    backends.push_back({"WoodenHaptics over HID", [](auto& wire) {
                            auto transport = std::make_unique<test::FakeTransport>();
                            auto* fake = transport.get();
                            wire = [fake] {
                                // The milliamps on the wire back to the force they make: the device
                                // sits at its home pose (no report read), where currents = M F is linear.
                                const devices::WoodenHapticsProfile profile{};
                                const glm::dvec3 home = devices::woodenhaptics_angles(profile, {});
                                glm::dmat3 m(0.0);
                                for (int axis = 0; axis < 3; ++axis) {
                                    glm::dvec3 unit(0.0);
                                    unit[axis] = 1.0;
                                    const auto c = devices::woodenhaptics_currents(profile, home, unit);
                                    m[axis] = glm::dvec3{c[0], c[1], c[2]};
                                }
                                const glm::dmat3 inverse = glm::inverse(m);
                                std::vector<glm::dvec3> f;
                                for (const auto& b : fake->written) {
                                    auto ma = [&](int k) { return static_cast<double>(static_cast<std::int16_t>(b[1 + 2 * k] | (b[2 + 2 * k] << 8))); };
                                    f.push_back(devices::woodenhaptics_to_device_frame(inverse * glm::dvec3{ma(0), ma(1), ma(2)}));
                                }
                                return f;
                            };
                            return std::unique_ptr<devices::HapticDevice>(
                                std::make_unique<devices::WoodenHapticsDevice>(std::move(transport), devices::WoodenHapticsProfile{}));
                        }});
    for (const auto& backend : backends) {
        SCOPED_TRACE(backend.name);
        auto w = world_with_one_hand();
        std::function<std::vector<glm::dvec3>()> wire;
        w->attach_device(0, backend.make(wire));
        ASSERT_NE(dynamic_cast<devices::SafeForceDevice*>(w->hand_devices[0].get()), nullptr) << "wrapped when attached";
        // A reconnecting device is opened on a thread of its own: wait until it is there.
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (!w->hand_devices[0]->poll(0) && std::chrono::steady_clock::now() < give_up) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        sched::DeterministicClock clock(w->schedule);
        const bool hid = backend.name.find("HID") != std::string::npos;
        // At about real time (the chain's clock is the wall's): 150 ms above the table, then pressed.
        const auto run_real_time = [&](int ms) {
            for (int tick = 0; tick < ms; ++tick) {
                clock.run_for_us(1'000);
                std::this_thread::sleep_for(std::chrono::microseconds(1'000));
            }
        };
        probe_height_m = 0.15;
        run_real_time(150);
        probe_height_m = -0.05;
        if (hid) {
            run_real_time(50);
        } else {
            // The ramp takes 0.5 s of wall time, and a loaded machine's stalls cost it some of its
            // level: pressed until the wire reaches the limit, 10 s at most.
            const auto give_up_at = std::chrono::steady_clock::now() + std::chrono::seconds(10);
            const auto reached = [&] {
                const auto now = wire();
                return !now.empty() && glm::length(now.back()) > 2.9;
            };
            while (!reached() && std::chrono::steady_clock::now() < give_up_at) run_real_time(50);
        }
        const auto& hand = w->sim.get<components::HandForce>(w->hands[0]);
        const auto sent = wire();
        ASSERT_GT(sent.size(), 100u);
        EXPECT_LT(glm::length(sent.front()), 0.31) << "the first force starts from zero";
        double most = 0.0;
        for (const auto& f : sent) {
            ASSERT_LE(glm::length(f), 3.0 + 0.01); // 0.01 N: whole milliamps on the WoodenHaptics wire
            most = std::max(most, glm::length(f));
        }
        if (!hid) {
            EXPECT_GT(glm::length(hand.force_n), 3.0) << "the hand asks for more than any device may give";
            EXPECT_GE(dynamic_cast<devices::SafeForceDevice&>(*w->hand_devices[0]).counters().engagements, 1u);
            EXPECT_GT(most, 2.9) << "engaged, the force on the wire rose to the limit";
        }
    }
}

// A hand resting inside the table asks 24 N from the first tick. Engaging into that would throw the
// handle up at the device's full force the moment the ramp allowed it; the chain waits until the force
// asked has been small for a moment (the handle lifted out of the table), then ramps. Each backend.
TEST(ForceSafety, AHandInsideTheTableIsNotPushedUntilItsForceIsSmall) {
    for (const bool lift : {false, true}) {
        SCOPED_TRACE(lift ? "lifted out after 0.3 s" : "left inside");
        auto w = world_with_one_hand();
        std::vector<glm::dvec3> sent;
        auto probe = std::make_unique<Probe>(sent);
        auto* raw = probe.get();
        w->attach_device(0, std::move(probe));
        sched::DeterministicClock clock(w->schedule);
        clock.run_for_us(300'000);
        ASSERT_FALSE(sent.empty());
        EXPECT_GT(glm::length(w->sim.get<components::HandForce>(w->hands[0]).force_n), 10.0) << "the hand asks for a lot";
        double most = 0.0;
        for (const auto& f : sent) most = std::max(most, glm::length(f));
        EXPECT_EQ(most, 0.0) << "nothing reaches the wire while the force asked is large";
        EXPECT_EQ(w->hand_devices[0]->last_sent().held, devices::ForceHeld::waiting);
        if (!lift) continue;
        raw->height_m = 0.009; // lifted until it only just presses on the table: the hand asks about 0.4 N
        sent.clear();
        // The chain waits on the wall clock (a real device's): run at about real time until the wire
        // carries 0.1 N (a loaded machine's stalls slow the ramp), 10 s at most.
        const auto give_up_at = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        most = 0.0;
        while (most <= 0.1 && std::chrono::steady_clock::now() < give_up_at) {
            clock.run_for_us(1'000);
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            if (!sent.empty()) most = std::max(most, glm::length(sent.back()));
        }
        for (const auto& f : sent) most = std::max(most, glm::length(f));
        EXPECT_EQ(dynamic_cast<devices::SafeForceDevice&>(*w->hand_devices[0]).counters().engagements, 1u) << "engaged once the force was small";
        EXPECT_GT(most, 0.1) << "and then it pushes";
        EXPECT_LT(most, 1.0);
    }
}

// Attaching never wraps twice, and devices without force output stay as they are.
TEST(ForceSafety, WrapsOnceAndLeavesInputOnlyDevicesAlone) {
    std::vector<glm::dvec3> sent;
    auto once = devices::make_force_safe(std::make_unique<Probe>(sent));
    auto* first = once.get();
    auto twice = devices::make_force_safe(std::move(once));
    EXPECT_EQ(twice.get(), first);
    auto probe = std::make_unique<Probe>(sent);
    probe->caps.has_force_output = false;
    auto* raw = probe.get();
    EXPECT_EQ(devices::make_force_safe(std::move(probe)).get(), raw);
}

// The virtual coupling was 400 N/m and 2 N s/m for every device, and WoodenHaptics' declared maximum
// stiffness and damping were read and never used: above them a device goes unstable and buzzes. Each
// shipped profile's coupling, capped by what the device declares, and the force it makes.
TEST(ForceSafety, TheCouplingIsEachProfilesOwnCappedByWhatTheDeviceRendersStably) {
    const auto coupling_of = [](std::unique_ptr<devices::HapticDevice> device) {
        auto w = world_with_one_hand();
        w->attach_device(0, std::move(device));
        const auto* coupling = w->sim.resource<const systems::HandCoupling>();
        return std::pair{coupling->n_per_m[0], coupling->damping_ns_per_m[0]};
    };
    const auto diy = coupling_of(std::make_unique<devices::DiyForceDevice>(std::make_unique<test::FakeTransport>()));
    EXPECT_EQ(diy, (std::pair{devices::diy_coupling_n_per_m, devices::diy_coupling_damping_ns_per_m})) << "DIY: protocol v1 declares no maximum";
    const auto shipped = devices::load_woodenhaptics_profile(woodenhaptics_profile_path());
    ASSERT_TRUE(shipped) << shipped.error().message;
    EXPECT_EQ(shipped->max_stiffness_n_per_m, 1000.0);
    EXPECT_EQ(coupling_of(std::make_unique<devices::WoodenHapticsDevice>(std::make_unique<test::FakeTransport>(), *shipped)), (std::pair{400.0, 2.0}))
        << "WoodenHaptics as published: 400 N/m and 2 N s/m are within its 1000 N/m and 8 N s/m";
    auto soft = *shipped;
    soft.max_stiffness_n_per_m = 250.0;
    soft.max_damping_ns_per_m = 1.0;
    EXPECT_EQ(coupling_of(std::make_unique<devices::WoodenHapticsDevice>(std::make_unique<test::FakeTransport>(), soft)), (std::pair{250.0, 1.0}))
        << "a build that declares less gets no more";
    EXPECT_EQ(coupling_of(std::make_unique<devices::SpaceMouseDevice>(std::make_unique<test::FakeTransport>(), *devices::find_spacemouse_profile(0x256f, 0xc62e))),
              (std::pair{400.0, 2.0}))
        << "a SpaceMouse pushes nothing; its hand keeps the default";

    // And the hand feels it: pressed 6 cm into the table, 400 N/m asks 24 N, a 250 N/m device 15 N.
    for (const double stiffness : {0.0, 250.0}) {
        auto w = world_with_one_hand();
        std::vector<glm::dvec3> sent;
        auto probe = std::make_unique<Probe>(sent);
        probe->caps.max_stiffness_n_per_m = stiffness;
        w->attach_device(0, std::move(probe));
        sched::DeterministicClock clock(w->schedule);
        clock.run_for_us(50'000);
        const double asked = w->sim.get<components::HandForce>(w->hands[0]).force_n.z;
        const double gap_m = w->sim.get<components::HandProxy>(w->hands[0]).position_m.z - w->sim.get<components::HandInput>(w->hands[0]).device_m.z;
        EXPECT_NEAR(asked, (stiffness > 0.0 ? stiffness : 400.0) * gap_m, 1e-6) << stiffness;
    }
}

// A device whose writes fail, in a world: the force system counts each failure for the HUD (the one
// declared access a demonstration never uses, LessonDemo.TheShokaDemoBends...), the link is said lost.
TEST(ForceSafety, AWorldCountsTheWritesItsDeviceRefusedAndSaysTheLinkIsLost) {
    struct Refusing final : devices::HapticDevice {
        devices::DeviceCapabilities caps{"refusing", true, 10.0, glm::dvec3{0.1}, true};
        const devices::DeviceCapabilities& capabilities() const override { return caps; }
        Result<devices::DeviceSample> poll(std::int64_t now_us) override {
            devices::DeviceSample s;
            s.time_us = now_us;
            s.position = {0.3, 0.3, 0.1};
            return s;
        }
        Result<void> send_force(glm::dvec3) override { return make_error(ErrorCode::io_error, "the wire refused"); }
    };
    auto w = world_with_one_hand();
    w->attach_device(0, std::make_unique<Refusing>());
    sched::DeterministicClock clock(w->schedule);
    clock.run_for_us(200'000);
    const auto* links = w->sim.resource<const systems::HandLinks>();
    ASSERT_NE(links, nullptr);
    EXPECT_GE(links->write_failures[0], 1u);
    EXPECT_EQ(links->link[0], components::DeviceLink::lost);
    for (const auto& line : w->schedule.unused_access()) EXPECT_EQ(line.find("'hand_force' declares writing 'systems::HandLinks'"), std::string::npos) << line;
}
