#include <gtest/gtest.h>

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

TEST(ReconnectingDevice, DropsAnUnpluggedDeviceAndReopensItWhenItIsBack) {
    Plug plug;
    ReconnectingDevice device(
        [&]() -> Result<std::unique_ptr<HapticDevice>> {
            ++plug.opens;
            if (!plug.plugged) return make_error(ErrorCode::device_error, "no such device");
            return std::unique_ptr<HapticDevice>(std::make_unique<PlugDevice>(plug));
        },
        DeviceCapabilities{"plug", true, 3.0, glm::dvec3{0.1}, true}, 500'000);
    EXPECT_TRUE(device.poll(0));
    EXPECT_TRUE(device.attached());
    plug.plugged = false;
    EXPECT_FALSE(device.poll(1000)) << "the unplugging is reported";
    EXPECT_FALSE(device.attached());
    EXPECT_TRUE(device.send_force({0, 0, 1})) << "forces go nowhere, without error, while unplugged";
    EXPECT_FALSE(device.poll(2000));
    EXPECT_EQ(plug.opens, 1) << "no reopening before the retry time";
    EXPECT_FALSE(device.poll(600'000)) << "tried again, still unplugged";
    EXPECT_EQ(plug.opens, 2);
    plug.plugged = true;
    EXPECT_FALSE(device.poll(700'000)) << "waits for the next retry";
    EXPECT_TRUE(device.poll(1'200'000)) << "re-attached";
    EXPECT_EQ(device.reconnects(), 1u);
}
