#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "engine/devices/diy_protocol.hpp"

using namespace ikebana::devices::diy;

TEST(DiyProtocol, Crc8MatchesTheSmbusCheckValue) {
    const std::string check = "123456789";
    EXPECT_EQ(crc8(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(check.data()), check.size())), 0xF4);
}

TEST(DiyProtocol, StateReportRoundTrips) {
    StateReport s{513, 512, {120000, -4500, 7}, {10, -20, 30}, 0x0005, status::motors_enabled, 3.3};
    const auto bytes = encode_state(s);
    EXPECT_EQ(bytes[0], state_report_id);
    const auto back = decode_state(bytes);
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->sequence, 513);
    EXPECT_EQ(back->acknowledged, 512);
    EXPECT_EQ(back->position_um, glm::ivec3(120000, -4500, 7));
    EXPECT_EQ(back->rotation_mrad, glm::i16vec3(10, -20, 30));
    EXPECT_EQ(back->buttons, 5);
    EXPECT_NEAR(back->max_force_n, 3.3, 1e-12);
}

// A fixture written out byte by byte, as a firmware author would check against.
TEST(DiyProtocol, ForceReportBytesAreAsDocumented) {
    const auto b = encode_force(ForceReport{0x0102, {1.5, -0.25, 0.0}, true, 2});
    const std::vector<std::uint8_t> head(b.begin(), b.begin() + 12);
    EXPECT_EQ(head, (std::vector<std::uint8_t>{0x20, 0x01, 0x02, 0x01, 0xdc, 0x05, 0x06, 0xff, 0x00, 0x00, 0x01, 0x02}));
    for (std::size_t i = 12; i < 31; ++i) EXPECT_EQ(b[i], 0) << "reserved byte " << i;
    EXPECT_EQ(b[31], crc8(std::span<const std::uint8_t>(b).first(31)));
}

TEST(DiyProtocol, ForceIsSaturatedAndNeverNaN) {
    const auto back = decode_force(encode_force(ForceReport{1, {1e9, -1e9, std::nan("")}, true, 2}));
    ASSERT_TRUE(back);
    EXPECT_NEAR(back->force_n.x, 32.767, 1e-9);
    EXPECT_NEAR(back->force_n.y, -32.767, 1e-9);
    EXPECT_EQ(back->force_n.z, 0.0);
}

TEST(DiyProtocol, TruncatedOversizedForeignAndCorruptReportsAreRefused) {
    const auto good = encode_state(StateReport{1, 0, {0, 0, 0}, {0, 0, 0}, 0, 0, 3.0});
    std::vector<std::uint8_t> truncated(good.begin(), good.begin() + 20);
    const auto t = decode_state(truncated);
    ASSERT_FALSE(t);
    EXPECT_NE(t.error().message.find("20 bytes, expected 32"), std::string::npos);
    std::vector<std::uint8_t> oversized(good.begin(), good.end());
    oversized.push_back(0);
    EXPECT_FALSE(decode_state(oversized));
    auto corrupt = good;
    corrupt[8] ^= 0x10;
    const auto c = decode_state(corrupt);
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("CRC"), std::string::npos);
    auto other_version = good;
    other_version[1] = 2;
    other_version[31] = crc8(std::span<const std::uint8_t>(other_version).first(31));
    EXPECT_FALSE(decode_state(other_version));
    EXPECT_FALSE(decode_state(encode_force(ForceReport{1, {0, 0, 0}, false, 2}))) << "a force report is not a state report";
}

TEST(DiyProtocol, RandomBytesAreRefusedNotMisread) {
    std::mt19937_64 rng(3);
    int accepted = 0;
    for (int i = 0; i < 50000; ++i) {
        std::vector<std::uint8_t> bytes(rng() % 40);
        for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
        if (bytes.size() > 1) {
            bytes[0] = state_report_id;
            bytes[1] = protocol_version;
        }
        accepted += decode_state(bytes).ok();
    }
    // Only the 1-in-256 random CRC matches among the right-sized ones get through.
    EXPECT_LT(accepted, 20);
}

TEST(DiyProtocol, SequenceTrackerRefusesReplaysAndCountsLosses) {
    SequenceTracker t;
    EXPECT_TRUE(t.accept(10));
    EXPECT_TRUE(t.accept(11));
    EXPECT_FALSE(t.accept(11)) << "a replay";
    EXPECT_FALSE(t.accept(5)) << "older";
    EXPECT_TRUE(t.accept(14));
    EXPECT_EQ(t.lost(), 2u);
    EXPECT_FALSE(t.accept(0xffff)) << "from 14, 0xffff is two behind, not 65521 ahead";
    EXPECT_EQ(t.refused(), 3u);
    SequenceTracker wrap;
    EXPECT_TRUE(wrap.accept(0xfffe));
    EXPECT_TRUE(wrap.accept(0xffff));
    EXPECT_TRUE(wrap.accept(0)) << "wraps around";
    EXPECT_TRUE(wrap.accept(1));
    EXPECT_EQ(wrap.lost(), 0u);
}
