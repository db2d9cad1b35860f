#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <fstream>
#include <mutex>
#include <numbers>
#include <thread>
#include <vector>

#include "engine/devices/hid_devices.hpp"
#include "tests/support/fake_transport.hpp"
#include "engine/devices/woodenhaptics.hpp"

using namespace ikebana;
using namespace ikebana::devices;

namespace {

using ikebana::test::FakeTransport;

// The device's input report for counts a, b, c (spare 0), little-endian.
std::vector<std::uint8_t> report(std::int16_t a, std::int16_t b, std::int16_t c) {
    std::vector<std::uint8_t> out;
    for (const std::int16_t v : {a, b, c, std::int16_t{0}}) {
        const auto u = static_cast<std::uint16_t>(v);
        out.push_back(static_cast<std::uint8_t>(u & 0xff));
        out.push_back(static_cast<std::uint8_t>(u >> 8));
    }
    return out;
}

std::vector<std::uint8_t> bytes_of(const std::array<std::uint8_t, woodenhaptics_output_size>& a) { return {a.begin(), a.end()}; }

// Poses spread over the workspace and beyond it (theta_a, theta_b, theta_c).
const std::vector<glm::dvec3> poses{
    {0.0, 0.0, std::numbers::pi / 2}, {-0.6, 0.4, 1.1}, {0.9, -0.3, 0.5}, {0.2, 1.0, 2.0}, {-1.3, 0.7, 0.2}};
const std::vector<glm::dvec3> forces{{1.0, 0.0, 0.0}, {0.0, -2.0, 0.0}, {0.0, 0.0, 3.0}, {1.5, -0.7, 2.2}};

// The hand-calculated pose: counts (4000, -2000, 2000) on the default profile.
constexpr WoodenHapticsCounts known_counts{4000, -2000, 2000, 0};
// Worked by hand from the published geometry (capstans 10 mm, drums 160/120/120 mm, 2000 counts per
// motor turn, lengths a..c 80, 205, 245 mm, workspace origin (220, 0, 80) mm):
//   theta_a = -2 pi 4000/2000 / 16         = -pi/4  (-45 deg)
//   theta_b = -2 pi (-2000)/2000 / 12      =  pi/6  ( 30 deg)
//   theta_c = pi/2 - 2 pi 2000/2000 / 12   =  pi/3  ( 60 deg)
//   reach   = 0.205 sin 30 + 0.245 sin 60  = 0.1025 + 0.2121762 = 0.3146762 m
//   x = reach cos(-45) - 0.220             = 0.2225097 - 0.220 =  0.0025097 m
//   y = reach sin(-45) - 0                 = -0.2225097 m
//   z = 0.080 + 0.205 cos 30 - 0.245 cos 60 - 0.080 = 0.1775352 - 0.1225 = 0.0550352 m
constexpr glm::dvec3 known_position_m{0.0025097, -0.2225097, 0.0550352};

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() / name;
    std::ofstream(path) << text;
    return path;
}

std::string shipped_text() {
    std::ifstream in(std::filesystem::path(IKEBANA_ASSET_DIR) / "devices" / "woodenhaptics.json");
    return {std::istreambuf_iterator<char>(in), {}};
}

} // namespace

// ---- the wire --------------------------------------------------------------------------------------

TEST(WoodenHaptics, InputReportIsFourLittleEndianInt16) {
    const std::vector<std::uint8_t> bytes{0x34, 0x12, 0xff, 0xff, 0x00, 0x80, 0x01, 0x00};
    const auto counts = decode_woodenhaptics_report(bytes);
    ASSERT_TRUE(counts);
    EXPECT_EQ(*counts, (WoodenHapticsCounts{0x1234, -1, -32768, 1}));
}

TEST(WoodenHaptics, InputReportsOfTheWrongSizeAreRefused) {
    for (const std::size_t size : {0u, 1u, 7u, 9u, 48u, 64u}) {
        const std::vector<std::uint8_t> bytes(size, 0);
        EXPECT_FALSE(decode_woodenhaptics_report(bytes)) << size << " bytes";
    }
}

TEST(WoodenHaptics, CurrentReportIsReportIdZeroThenLittleEndianMilliamps) {
    const auto b = encode_woodenhaptics_currents({1000.0, -2.0, 258.0});
    EXPECT_EQ(bytes_of(b), (std::vector<std::uint8_t>{0x00, 0xe8, 0x03, 0xfe, 0xff, 0x02, 0x01, 0x00, 0x00}));
}

TEST(WoodenHaptics, CurrentsAreRoundedClampedToThreeAmpsAndNeverNaN) {
    EXPECT_EQ(bytes_of(encode_woodenhaptics_currents({5000.0, -1e9, 1.6})),
              (std::vector<std::uint8_t>{0x00, 0xb8, 0x0b, 0x48, 0xf4, 0x02, 0x00, 0x00, 0x00}))
        << "+3000, -3000, 2";
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(bytes_of(encode_woodenhaptics_currents({std::nan(""), inf, -inf})), std::vector<std::uint8_t>(9, 0));
}

// ---- kinematics ------------------------------------------------------------------------------------

TEST(WoodenHaptics, ZeroCountsIsTheHomePose) {
    const WoodenHapticsProfile p;
    const glm::dvec3 q = woodenhaptics_angles(p, {0, 0, 0, 0});
    EXPECT_EQ(q, glm::dvec3(0.0, 0.0, std::numbers::pi / 2)) << "upper arm up, forearm level";
    // The handle is a forearm's length out and an upper arm above the shoulder, less the origin.
    const glm::dvec3 home = woodenhaptics_position(p, q);
    EXPECT_NEAR(home.x, 0.245 - 0.220, 1e-12);
    EXPECT_NEAR(home.y, 0.0, 1e-12);
    EXPECT_NEAR(home.z, 0.080 + 0.205 - 0.080, 1e-12);
}

TEST(WoodenHaptics, KnownCountsGiveTheHandComputedPosition) {
    const WoodenHapticsProfile p;
    const glm::dvec3 q = woodenhaptics_angles(p, known_counts);
    EXPECT_NEAR(q.x, -std::numbers::pi / 4, 1e-12);
    EXPECT_NEAR(q.y, std::numbers::pi / 6, 1e-12);
    EXPECT_NEAR(q.z, std::numbers::pi / 3, 1e-12);
    const glm::dvec3 x = woodenhaptics_position(p, q);
    EXPECT_NEAR(x.x, known_position_m.x, 1e-7);
    EXPECT_NEAR(x.y, known_position_m.y, 1e-7);
    EXPECT_NEAR(x.z, known_position_m.z, 1e-7);
}

TEST(WoodenHaptics, JacobianMatchesCentralDifferencesOfTheKinematics) {
    const WoodenHapticsProfile p;
    const double h = 1e-5;
    for (const glm::dvec3& q : poses) {
        const glm::dmat3 j = woodenhaptics_jacobian(p, q);
        for (int joint = 0; joint < 3; ++joint) {
            glm::dvec3 step{0.0};
            step[joint] = h;
            const glm::dvec3 numeric = (woodenhaptics_position(p, q + step) - woodenhaptics_position(p, q - step)) / (2.0 * h);
            EXPECT_LE(glm::length(j[joint] - numeric), 1e-6 * glm::length(numeric))
                << "joint " << joint << " at (" << q.x << ", " << q.y << ", " << q.z << ")";
        }
    }
}

// tau . dq == F . dx: the joint torques do the work the force does, with dx from the kinematics
// themselves (not from the Jacobian the torques were made with).
TEST(WoodenHaptics, JointTorquesDoTheWorkOfTheForce) {
    const WoodenHapticsProfile p;
    const std::vector<glm::dvec3> directions{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.3, -0.8, 0.5}};
    for (const glm::dvec3& q : poses) {
        for (const glm::dvec3& f : forces) {
            const glm::dvec3 tau = woodenhaptics_joint_torques(p, q, f);
            for (const glm::dvec3& d : directions) {
                const glm::dvec3 dq = 1e-5 * d;
                const glm::dvec3 dx = woodenhaptics_position(p, q + dq) - woodenhaptics_position(p, q - dq);
                const double joint_work = glm::dot(tau, 2.0 * dq);
                const double handle_work = glm::dot(f, dx);
                EXPECT_NEAR(joint_work, handle_work, 1e-6 * glm::length(f) * glm::length(dx));
            }
        }
    }
}

// The same through the cables to the motors: one encoder count forward and back on motor i moves the
// handle by dx; the motor's torque (current times torque constant, in its encoder's direction) times
// that turn must do the force's work F . dx.
TEST(WoodenHaptics, MotorCurrentsDoTheWorkOfTheForceThroughTheCapstans) {
    const WoodenHapticsProfile p;
    const std::vector<WoodenHapticsCounts> pose_counts{{0, 0, 0, 0}, known_counts, {-1500, 1000, -800, 0}, {700, -3500, 4500, 0}};
    for (const auto& counts : pose_counts) {
        const glm::dvec3 q = woodenhaptics_angles(p, counts);
        for (const glm::dvec3& f : forces) {
            const auto mA = woodenhaptics_currents(p, q, f);
            for (std::size_t i = 0; i < 3; ++i) {
                auto forward = counts;
                auto back = counts;
                forward[i] = static_cast<std::int16_t>(forward[i] + 1);
                back[i] = static_cast<std::int16_t>(back[i] - 1);
                const glm::dvec3 dx = woodenhaptics_position(p, woodenhaptics_angles(p, forward)) -
                                      woodenhaptics_position(p, woodenhaptics_angles(p, back));
                const double motor_turn_rad = 2.0 * 2.0 * std::numbers::pi / p.encoder_counts_per_rev[i];
                const double motor_nm = woodenhaptics_current_direction[i] * mA[i] * 1e-3 * p.torque_constant_nm_per_a[i];
                EXPECT_NEAR(motor_nm * motor_turn_rad, glm::dot(f, dx), 1e-6 * glm::length(f) * glm::length(dx)) << "motor " << i;
            }
        }
    }
}

// Checked by hand: at home the forearm is level, so lifting the handle is motor c's alone:
// tau_c = 0.245 m x 1 N; through the 10:120 capstan 0.0204167 N m at the motor; / 0.0259 N m/A =
// 0.78829 A, negative because a positive count on c lowers the forearm.
TEST(WoodenHaptics, LiftingTheHandleAtHomeIsMotorCsAlone) {
    const WoodenHapticsProfile p;
    const auto mA = woodenhaptics_currents(p, woodenhaptics_angles(p, {0, 0, 0, 0}), {0.0, 0.0, 1.0});
    EXPECT_NEAR(mA[0], 0.0, 1e-9);
    EXPECT_NEAR(mA[1], 0.0, 1e-9);
    EXPECT_NEAR(mA[2], -788.288, 1e-3);
}

// ---- the device, through a fake transport ------------------------------------------------------------

TEST(WoodenHaptics, CapabilitiesComeFromTheProfile) {
    WoodenHapticsProfile profile;
    profile.max_force_n = 4.0;
    profile.workspace_radius_m = 0.09;
    WoodenHapticsDevice device(std::make_unique<FakeTransport>(), profile);
    const auto& caps = device.capabilities();
    EXPECT_TRUE(caps.has_force_output);
    EXPECT_TRUE(caps.reports_position);
    EXPECT_DOUBLE_EQ(caps.max_force_n, 4.0);
    EXPECT_EQ(caps.workspace_half_extent_m, glm::dvec3(0.09));
    EXPECT_EQ(caps.name, profile.name);
}

TEST(WoodenHaptics, PollReturnsTheNewestReportsPositionInTheDeviceFrame) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    fake->inbound = {report(0, 0, 0), report(known_counts[0], known_counts[1], known_counts[2])};
    WoodenHapticsDevice device(std::move(transport), WoodenHapticsProfile{});
    const auto s = device.poll(1000);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->time_us, 1000);
    // Device frame: x right (WoodenHaptics y), y away from the user (-x, which points at the user), z up.
    EXPECT_NEAR(s->position.x, known_position_m.y, 1e-7);
    EXPECT_NEAR(s->position.y, -known_position_m.x, 1e-7);
    EXPECT_NEAR(s->position.z, known_position_m.z, 1e-7);
    EXPECT_EQ(s->buttons, 0u) << "the 2017 firmware has no buttons";
    EXPECT_EQ(device.reports_refused(), 0u);
}

TEST(WoodenHaptics, MalformedReportsAreCountedAndSkipped) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    auto truncated = report(1, 2, 3);
    truncated.pop_back();
    auto oversized = report(100, 200, 300);
    oversized.push_back(0);
    fake->inbound = {report(known_counts[0], known_counts[1], known_counts[2]), truncated, oversized, std::vector<std::uint8_t>(64, 0xff)};
    WoodenHapticsDevice device(std::move(transport), WoodenHapticsProfile{});
    const auto s = device.poll(1000);
    ASSERT_TRUE(s);
    EXPECT_EQ(device.reports_refused(), 3u);
    EXPECT_EQ(device.last_counts(), known_counts) << "the good report stands";
    EXPECT_NEAR(s->position.z, known_position_m.z, 1e-7);
}

TEST(WoodenHaptics, PollIsBoundedAndReportsUnplugging) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    for (int i = 0; i < 1000; ++i) fake->inbound.push_back(report(static_cast<std::int16_t>(i), 0, 0));
    WoodenHapticsDevice device(std::move(transport), WoodenHapticsProfile{});
    ASSERT_TRUE(device.poll(1000));
    EXPECT_GT(fake->inbound.size(), 900u) << "one poll must not drain a flood";
    fake->unplugged = true;
    EXPECT_FALSE(device.poll(2000)) << "unplugging is reported, not hidden";
}

TEST(WoodenHaptics, SendForceWritesTheJacobianTransposeCurrents) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    WoodenHapticsDevice device(std::move(transport), WoodenHapticsProfile{});
    // At home (no report yet): 1 N up is -788 mA on motor c (see LiftingTheHandleAtHomeIsMotorCsAlone).
    ASSERT_TRUE(device.poll(1000));
    ASSERT_TRUE(device.send_force({0.0, 0.0, 1.0}));
    ASSERT_EQ(fake->written.size(), 1u);
    EXPECT_EQ(fake->written[0], (std::vector<std::uint8_t>{0x00, 0x00, 0x00, 0x00, 0x00, 0xec, 0xfc, 0x00, 0x00}));
    // Elsewhere: whatever the pure functions say for the force turned into the WoodenHaptics frame.
    fake->inbound = {report(known_counts[0], known_counts[1], known_counts[2])};
    ASSERT_TRUE(device.poll(2000));
    const glm::dvec3 force_device{0.8, -0.5, 1.2};
    ASSERT_TRUE(device.send_force(force_device));
    const WoodenHapticsProfile p;
    const auto expected = encode_woodenhaptics_currents(
        woodenhaptics_currents(p, woodenhaptics_angles(p, known_counts), glm::dvec3{0.5, 0.8, 1.2}));
    EXPECT_EQ(fake->written.back(), bytes_of(expected));
}

// The safety layer (SafeForceDevice) clamps; the device must not quietly clamp again to a different
// limit. Only the protocol's +-3000 mA remains.
TEST(WoodenHaptics, DeviceLeavesClampingToTheSafetyLayer) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    WoodenHapticsProfile profile;
    profile.max_force_n = 1.0;
    WoodenHapticsDevice device(std::move(transport), profile);
    ASSERT_TRUE(device.poll(1000));
    ASSERT_TRUE(device.send_force({0.0, 0.0, 2.0}));
    EXPECT_EQ(fake->written.back(), bytes_of(encode_woodenhaptics_currents({0.0, 0.0, -2.0 * 788.288})));
}

TEST(WoodenHaptics, ZeroForceWritesZeroCurrents) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    std::unique_ptr<HapticDevice> device = std::make_unique<WoodenHapticsDevice>(std::move(transport), WoodenHapticsProfile{});
    ASSERT_TRUE(device->zero_force());
    ASSERT_EQ(fake->written.size(), 1u);
    EXPECT_EQ(fake->written[0], std::vector<std::uint8_t>(9, 0));
}

// The force watchdog zeroes from its own thread while the haptic loop polls and sends.
TEST(WoodenHaptics, ZeroForceFromAnotherThreadIsSafe) {
    auto transport = std::make_unique<FakeTransport>();
    auto* fake = transport.get();
    WoodenHapticsDevice device(std::move(transport), WoodenHapticsProfile{});
    std::thread watchdog([&] {
        for (int i = 0; i < 500; ++i) (void)device.zero_force();
    });
    for (int tick = 1; tick <= 500; ++tick) {
        (void)device.poll(tick * 1000);
        (void)device.send_force({0.0, 0.0, 1.0});
    }
    watchdog.join();
    std::lock_guard lock(fake->mutex);
    EXPECT_EQ(fake->written.size(), 1000u);
    for (const auto& w : fake->written) EXPECT_EQ(w.size(), woodenhaptics_output_size);
}

TEST(WoodenHaptics, MatchHidDeviceRecognisesTheRawHidIds) {
    const auto match = match_hid_device({0x1234, 0x0006, "/dev/hidraw3", "KTH", "WoodenHaptics"});
    EXPECT_EQ(match.kind, DeviceMatch::Kind::woodenhaptics);
    EXPECT_FALSE(match.profile.empty());
    EXPECT_EQ(match_hid_device({0x1234, 0x0007, "", "", ""}).kind, DeviceMatch::Kind::unknown);
}

// ---- the profile file -----------------------------------------------------------------------------------

TEST(WoodenHaptics, ShippedProfileLoadsWithThePublishedDefaults) {
    const auto loaded = load_woodenhaptics_profile(std::filesystem::path(IKEBANA_ASSET_DIR) / "devices" / "woodenhaptics.json");
    ASSERT_TRUE(loaded) << loaded.error().message;
    const WoodenHapticsProfile defaults;
    EXPECT_EQ(loaded->name, defaults.name);
    EXPECT_EQ(loaded->length_body_a_m, defaults.length_body_a_m);
    EXPECT_EQ(loaded->length_body_b_m, defaults.length_body_b_m);
    EXPECT_EQ(loaded->length_body_c_m, defaults.length_body_c_m);
    EXPECT_EQ(loaded->capstan_diameter_m, defaults.capstan_diameter_m);
    EXPECT_EQ(loaded->drum_diameter_m, defaults.drum_diameter_m);
    EXPECT_EQ(loaded->workspace_origin_m, defaults.workspace_origin_m);
    EXPECT_EQ(loaded->workspace_radius_m, defaults.workspace_radius_m);
    EXPECT_EQ(loaded->torque_constant_nm_per_a, defaults.torque_constant_nm_per_a);
    EXPECT_EQ(loaded->encoder_counts_per_rev, defaults.encoder_counts_per_rev);
    EXPECT_EQ(loaded->max_force_n, defaults.max_force_n);
    EXPECT_EQ(loaded->max_stiffness_n_per_m, defaults.max_stiffness_n_per_m);
    EXPECT_EQ(loaded->max_damping_ns_per_m, defaults.max_damping_ns_per_m);
}

TEST(WoodenHaptics, ABadFieldIsNamedWithItsFileAndPath) {
    std::string text = shipped_text();
    ASSERT_FALSE(text.empty());
    const auto replace = [&](const std::string& from, const std::string& to) {
        const auto at = text.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        text.replace(at, from.size(), to);
    };
    replace("\"length_body_b_m\": 0.205", "\"length_body_b_m\": 205");
    replace("[0.0259, 0.0259, 0.0259]", "[0.0259, \"strong\", 0.0259]");
    replace("[2000, 2000, 2000]", "[2000, 2000.5, 2000]");
    const auto path = write_temp("ikebana_woodenhaptics_bad.json", text);
    const auto loaded = load_woodenhaptics_profile(path);
    ASSERT_FALSE(loaded);
    const std::string& message = loaded.error().message;
    EXPECT_NE(message.find(path.string() + ": /length_body_b_m: expected a number in (0, 1], got 205"), std::string::npos) << message;
    EXPECT_NE(message.find(path.string() + ": /torque_constant_nm_per_a/1: "), std::string::npos) << message;
    EXPECT_NE(message.find(path.string() + ": /encoder_counts_per_rev/1: expected a whole number"), std::string::npos) << message;
    std::filesystem::remove(path);
}

TEST(WoodenHaptics, AnUnknownKeyIsRefused) {
    std::string text = shipped_text();
    const auto at = text.find("\"max_force_n\"");
    ASSERT_NE(at, std::string::npos);
    text.insert(at, "\"max_forse_n\": 5.0,\n  ");
    const auto path = write_temp("ikebana_woodenhaptics_unknown.json", text);
    const auto loaded = load_woodenhaptics_profile(path);
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find(path.string() + ": /max_forse_n: unknown field"), std::string::npos) << loaded.error().message;
    std::filesystem::remove(path);
}

TEST(WoodenHaptics, AWrongNumberOfMotorsIsRefused) {
    std::string text = shipped_text();
    const auto at = text.find("[0.160, 0.120, 0.120]");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 21, "[0.160, 0.120, 0.120, 0.1]");
    const auto loaded = parse_woodenhaptics_profile(text, "mine.json");
    ASSERT_FALSE(loaded);
    EXPECT_NE(loaded.error().message.find("mine.json: /drum_diameter_m: expected 3 numbers"), std::string::npos) << loaded.error().message;
}

TEST(WoodenHaptics, AMissingProfileFileIsNotFound) {
    const auto loaded = load_woodenhaptics_profile("/nonexistent/woodenhaptics.json");
    ASSERT_FALSE(loaded);
    EXPECT_EQ(loaded.error().code, ErrorCode::not_found);
}
