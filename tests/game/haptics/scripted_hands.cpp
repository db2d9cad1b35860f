#include "scripted_hands.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace ikebana::test {

std::unique_ptr<devices::ScriptedDevice> script(const std::vector<Key>& keys) {
    std::ostringstream csv;
    csv << "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n";
    for (const auto& k : keys) csv << k.t << "," << k.x << "," << k.y << "," << k.z << ",0,0,0," << k.buttons << "\n";
    auto parsed = devices::parse_trajectory(csv.str(), "test");
    EXPECT_TRUE(parsed) << (parsed ? "" : parsed.error().message);
    return std::make_unique<devices::ScriptedDevice>(std::move(parsed).value(), devices::ScriptedDevice::Mode::interpolate);
}

} // namespace ikebana::test
