#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "engine/devices/spacemouse.hpp"

using namespace ikebana::devices;

namespace {
SpaceMouseParser navigator() { return SpaceMouseParser(*find_spacemouse_profile(0x046d, 0xc626)); }
SpaceMouseParser wireless() { return SpaceMouseParser(*find_spacemouse_profile(0x256f, 0xc62e)); }
} // namespace

TEST(SpaceMouse, ProfilesCoverBothVendors) {
    EXPECT_TRUE(find_spacemouse_profile(0x046d, 0xc626)); // SpaceNavigator
    EXPECT_TRUE(find_spacemouse_profile(0x256f, 0xc635)); // SpaceMouse Compact
    EXPECT_FALSE(find_spacemouse_profile(0x1234, 0xc626));
}

// Older models: translation in report 1, rotation in report 2, buttons in report 3.
TEST(SpaceMouse, SplitReportsFillTranslationRotationAndButtons) {
    auto p = navigator();
    // x = +350 (full push), y = -175, z = 0
    ASSERT_TRUE(p.feed(std::vector<std::uint8_t>{0x01, 0x5e, 0x01, 0x51, 0xff, 0x00, 0x00}));
    // rx = 0, ry = -30 (0xffe2), rz = 35
    ASSERT_TRUE(p.feed(std::vector<std::uint8_t>{0x02, 0x00, 0x00, 0xe2, 0xff, 0x23, 0x00}));
    ASSERT_TRUE(p.feed(std::vector<std::uint8_t>{0x03, 0x03, 0x00}));
    const auto s = p.sample(5);
    EXPECT_DOUBLE_EQ(s.position.x, 1.0);
    EXPECT_DOUBLE_EQ(s.position.y, -0.5);
    EXPECT_DOUBLE_EQ(s.position.z, 0.0);
    EXPECT_NEAR(s.rotation.y, -30.0 / 350.0, 1e-12);
    EXPECT_NEAR(s.rotation.z, 0.1, 1e-12);
    EXPECT_EQ(s.buttons, 3u);
}

// Newer models: all six axes in one 13-byte report 1.
TEST(SpaceMouse, CombinedReportFillsAllSixAxes) {
    auto p = wireless();
    ASSERT_TRUE(p.feed(std::vector<std::uint8_t>{0x01, 0x5e, 0x01, 0, 0, 0, 0, 0, 0, 0, 0, 0xa2, 0xfe}));
    const auto s = p.sample(0);
    EXPECT_DOUBLE_EQ(s.position.x, 1.0);
    EXPECT_DOUBLE_EQ(s.rotation.z, -1.0);
}

TEST(SpaceMouse, OutOfRangeValuesAreClampedToFullScale) {
    auto p = navigator();
    ASSERT_TRUE(p.feed(std::vector<std::uint8_t>{0x01, 0xff, 0x7f, 0x00, 0x80, 0x00, 0x00}));
    EXPECT_DOUBLE_EQ(p.sample(0).position.x, 1.0);
    EXPECT_DOUBLE_EQ(p.sample(0).position.y, -1.0);
}

TEST(SpaceMouse, TruncatedAndOversizedReportsAreRefusedAndChangeNothing) {
    auto p = navigator();
    ASSERT_TRUE(p.feed(std::vector<std::uint8_t>{0x01, 0x5e, 0x01, 0x00, 0x00, 0x00, 0x00}));
    const auto before = p.sample(0);
    const auto truncated = p.feed(std::vector<std::uint8_t>{0x01, 0x00, 0x00});
    ASSERT_FALSE(truncated);
    EXPECT_NE(truncated.error().message.find("report 1 of 3 bytes"), std::string::npos) << truncated.error().message;
    EXPECT_FALSE(p.feed(std::vector<std::uint8_t>{0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}));
    EXPECT_FALSE(p.feed(std::vector<std::uint8_t>{}));
    EXPECT_FALSE(p.feed(std::vector<std::uint8_t>{0x03}));
    EXPECT_EQ(p.sample(0).position, before.position);
    EXPECT_EQ(p.reports_refused(), 4u);
    auto w = wireless();
    EXPECT_FALSE(w.feed(std::vector<std::uint8_t>{0x01, 0x5e, 0x01, 0, 0, 0, 0})) << "a combined device needs 13 bytes";
}

TEST(SpaceMouse, OtherReportIdsAreIgnored) {
    auto p = navigator();
    const auto led = p.feed(std::vector<std::uint8_t>{0x04, 0x01});
    ASSERT_TRUE(led);
    EXPECT_EQ(*led, ReportOutcome::ignored);
    const auto battery = p.feed(std::vector<std::uint8_t>{0x17, 0x64});
    ASSERT_TRUE(battery);
    EXPECT_EQ(*battery, ReportOutcome::ignored);
}

// Garbage never crashes the parser and never yields a value outside [-1, 1].
TEST(SpaceMouse, RandomBytesNeverCrashOrEscapeTheRange) {
    std::mt19937_64 rng(7);
    for (auto make : {navigator, wireless}) {
        auto p = make();
        for (int i = 0; i < 20000; ++i) {
            std::vector<std::uint8_t> report(rng() % 20);
            for (auto& b : report) b = static_cast<std::uint8_t>(rng() % 4 == 0 ? rng() % 4 : rng());
            (void)p.feed(report);
            const auto s = p.sample(0);
            for (int a = 0; a < 3; ++a) {
                ASSERT_LE(std::abs(s.position[a]), 1.0);
                ASSERT_LE(std::abs(s.rotation[a]), 1.0);
            }
        }
    }
}
