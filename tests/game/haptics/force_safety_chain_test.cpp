#include <gtest/gtest.h>

#include <deque>
#include <functional>
#include <mutex>

#include "components/hand.hpp"
#include "engine/devices/diy_protocol.hpp"
#include "engine/devices/hid_devices.hpp"
#include "engine/devices/reconnecting_device.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "engine/devices/woodenhaptics.hpp"
#include "engine/sched/clocks.hpp"
#include "game/scene/scene.hpp"
#include "game/world/world.hpp"
#include "tests/support/fake_transport.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {

// A force device of no particular backend, held 5 cm under the table top (its hand presses down).
struct Probe final : devices::HapticDevice {
    std::vector<glm::dvec3>& sent;
    devices::DeviceCapabilities caps{"probe", true, 10.0, glm::dvec3{0.1}, true};
    explicit Probe(std::vector<glm::dvec3>& s) : sent(s) {}
    const devices::DeviceCapabilities& capabilities() const override { return caps; }
    Result<devices::DeviceSample> poll(std::int64_t now_us) override {
        devices::DeviceSample s;
        s.time_us = now_us;
        s.position = {0.3, 0.3, -0.05};
        return s;
    }
    Result<void> send_force(glm::dvec3 f) override {
        sent.push_back(f);
        return {};
    }
};

std::unique_ptr<World> world_with_one_hand() {
    SceneDef scene{};
    scene.seed = 1;
    scene.gravity_m_s2 = {0, 0, -9.80665};
    scene.kenzan_layout = "standard";
    scene.kenzan_position_m = {0, 0, 0.008};
    scene.hands.push_back({0, {0.3, 0.3, 0.1}, 0.02, ""});
    auto w = World::create(scene);
    EXPECT_TRUE(w) << (w ? "" : w.error().message);
    return std::move(w).value();
}

struct Backend {
    std::string name;
    // Makes the device and says how to read back the forces that reached its wire, in newtons.
    std::function<std::unique_ptr<devices::HapticDevice>(std::function<std::vector<glm::dvec3>()>&)> make;
};

} // namespace

// Whichever backend a hand gets, the force on its wire went through the one safety layer: a hand
// pressed 5 cm into the table asks for 20 N and more, the wire never carries more than 3 N, and the
// first force sent starts from zero (the ramp).
TEST(ForceSafety, WrapsEveryForceDevice) {
    std::vector<Backend> backends;
    backends.push_back({"any force device", [](auto& wire) {
                            auto sent = std::make_shared<std::vector<glm::dvec3>>();
                            wire = [sent] { return *sent; };
                            return std::unique_ptr<devices::HapticDevice>(std::make_unique<Probe>(*sent));
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
                                    return std::unique_ptr<devices::HapticDevice>(std::make_unique<Probe>(*sent));
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
        sched::DeterministicClock clock(w->schedule);
        clock.run_for_us(300'000);
        const auto& hand = w->sim.get<components::HandForce>(w->hands[0]);
        const auto sent = wire();
        ASSERT_GT(sent.size(), 100u);
        if (backend.name.find("HID") == std::string::npos) {
            EXPECT_GT(glm::length(hand.force_n), 3.0) << "the hand asks for more than any device may give";
        }
        EXPECT_LT(glm::length(sent.front()), 0.31) << "the first force starts from zero";
        for (const auto& f : sent) ASSERT_LE(glm::length(f), 3.0 + 0.01); // 0.01 N: whole milliamps on the WoodenHaptics wire
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
