#include "engine/devices/woodenhaptics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"

namespace ikebana::devices {

namespace {

constexpr const char* profile_format = "ikebana-woodenhaptics/1";
// A flood of reports (a device sending faster than we poll) must not hold the haptic loop.
constexpr int max_reports_per_poll = 32;

std::int16_t to_current_mA(double mA) {
    if (!std::isfinite(mA)) return 0;
    return static_cast<std::int16_t>(std::lround(std::clamp(mA, -woodenhaptics_max_current_mA, woodenhaptics_max_current_mA)));
}

void put16(std::uint8_t* p, std::int16_t v) {
    const auto u = static_cast<std::uint16_t>(v);
    p[0] = static_cast<std::uint8_t>(u & 0xff);
    p[1] = static_cast<std::uint8_t>(u >> 8);
}

std::int16_t get16(const std::uint8_t* p) { return static_cast<std::int16_t>(static_cast<std::uint16_t>(p[0] | (p[1] << 8))); }

// Joint radians per motor radian: the cable reduction, and its sign. A positive count on any of the
// three encoders turns its joint the negative way (the published code reaches the same by negating
// count a and the reduction of b, and measuring c the other way round from the horizontal).
double joint_per_motor(const WoodenHapticsProfile& p, std::size_t i) { return -p.capstan_diameter_m[i] / p.drum_diameter_m[i]; }

// Exactly three numbers in `range` (per-motor parameters a, b, c).
std::optional<std::array<double, 3>> three(assets::JsonChecker& c, const assets::Json& root, const char* key, assets::NumberRange range) {
    const auto list = c.numbers(root, "", key, range, 3);
    if (!list) return std::nullopt;
    if (list->size() != 3) {
        c.problem(std::string("/") + key, "expected 3 numbers (motors a, b, c), got " + std::to_string(list->size()));
        return std::nullopt;
    }
    return std::array<double, 3>{(*list)[0], (*list)[1], (*list)[2]};
}

} // namespace

Result<WoodenHapticsProfile> parse_woodenhaptics_profile(std::string_view text, const std::string& label) {
    assets::JsonChecker c(label);
    const auto root = c.parse_object(text);
    if (!root) return c.error();
    c.no_unknown_keys(*root, "", {"format", "name", "notes", "length_body_a_m", "length_body_b_m", "length_body_c_m",
                                  "capstan_diameter_m", "drum_diameter_m", "workspace_origin_m", "workspace_radius_m",
                                  "torque_constant_nm_per_a", "encoder_counts_per_rev", "max_force_n", "max_stiffness_n_per_m",
                                  "max_damping_ns_per_m", "silent_after_ms"});
    const auto format = c.string(*root, "", "format");
    if (format && *format != profile_format) c.problem("/format", std::string("expected \"") + profile_format + "\", got \"" + *format + "\"");
    (void)c.string(*root, "", "notes", false);

    // Ranges wide enough for any desk-sized build, narrow enough to catch millimetres typed as metres.
    WoodenHapticsProfile p;
    p.name = c.string(*root, "", "name").value_or("");
    p.length_body_a_m = c.number(*root, "", "length_body_a_m", {0.0, 1.0}).value_or(0.0);
    p.length_body_b_m = c.number(*root, "", "length_body_b_m", {0.0, 1.0, true}).value_or(0.0);
    p.length_body_c_m = c.number(*root, "", "length_body_c_m", {0.0, 1.0, true}).value_or(0.0);
    p.capstan_diameter_m = three(c, *root, "capstan_diameter_m", {0.0, 0.1, true}).value_or(p.capstan_diameter_m);
    p.drum_diameter_m = three(c, *root, "drum_diameter_m", {0.0, 1.0, true}).value_or(p.drum_diameter_m);
    const auto origin = three(c, *root, "workspace_origin_m", {-1.0, 1.0});
    if (origin) p.workspace_origin_m = {(*origin)[0], (*origin)[1], (*origin)[2]};
    p.workspace_radius_m = c.number(*root, "", "workspace_radius_m", {0.0, 1.0, true}).value_or(0.0);
    p.torque_constant_nm_per_a = three(c, *root, "torque_constant_nm_per_a", {0.0, 10.0, true}).value_or(p.torque_constant_nm_per_a);
    if (const auto counts = three(c, *root, "encoder_counts_per_rev", {1.0, 1e7})) {
        for (std::size_t i = 0; i < 3; ++i) {
            if (std::floor((*counts)[i]) != (*counts)[i]) {
                c.problem("/encoder_counts_per_rev/" + std::to_string(i),
                          "expected a whole number of counts, got " + assets::JsonChecker::describe((*root)["encoder_counts_per_rev"][i]));
            }
        }
        p.encoder_counts_per_rev = *counts;
    }
    p.max_force_n = c.number(*root, "", "max_force_n", {0.0, 50.0, true}).value_or(0.0);
    p.max_stiffness_n_per_m = c.number(*root, "", "max_stiffness_n_per_m", {0.0, 1e5, true}).value_or(0.0);
    p.max_damping_ns_per_m = c.number(*root, "", "max_damping_ns_per_m", {0.0, 1000.0}).value_or(0.0);
    // Optional (files written before it: the published firmware's 20 ms): how long without a report
    // makes the device silent. Under 2 ms the loop's own jitter would trip it; over a second a hung
    // device would be pushed against for that long.
    if (root->contains("silent_after_ms")) p.silent_after_ms = c.number(*root, "", "silent_after_ms", {2.0, 1000.0}).value_or(p.silent_after_ms);
    if (!c.ok()) return c.error();
    return p;
}

Result<WoodenHapticsProfile> load_woodenhaptics_profile(const std::filesystem::path& path) {
    auto text = assets::read_text_file(path);
    if (!text) return std::move(text).error();
    return parse_woodenhaptics_profile(*text, path.string());
}

std::optional<WoodenHapticsCounts> decode_woodenhaptics_report(std::span<const std::uint8_t> bytes) {
    if (bytes.size() != woodenhaptics_input_size) return std::nullopt;
    return WoodenHapticsCounts{get16(&bytes[0]), get16(&bytes[2]), get16(&bytes[4]), get16(&bytes[6])};
}

std::array<std::uint8_t, woodenhaptics_output_size> encode_woodenhaptics_currents(std::array<double, 3> current_mA) {
    std::array<std::uint8_t, woodenhaptics_output_size> b{}; // b[0] = 0: the report id; b[7..8]: the spare word
    for (std::size_t i = 0; i < 3; ++i) put16(&b[1 + 2 * i], to_current_mA(current_mA[i]));
    return b;
}

glm::dvec3 woodenhaptics_angles(const WoodenHapticsProfile& p, const WoodenHapticsCounts& counts) {
    glm::dvec3 q;
    for (std::size_t i = 0; i < 3; ++i) {
        const double motor_rad = 2.0 * std::numbers::pi * counts[i] / p.encoder_counts_per_rev[i];
        q[static_cast<glm::length_t>(i)] = joint_per_motor(p, i) * motor_rad;
    }
    // The forearm's encoder is zero with the forearm level, which is theta_c = pi/2.
    q.z += std::numbers::pi / 2.0;
    return q;
}

glm::dvec3 woodenhaptics_position(const WoodenHapticsProfile& p, glm::dvec3 q) {
    // The arm is a vertical plane turned by theta_a; in it the handle is reach r out from the axis and
    // the shoulder's height plus the upper arm's rise minus the forearm's drop up.
    const double reach = p.length_body_b_m * std::sin(q.y) + p.length_body_c_m * std::sin(q.z);
    const glm::dvec3 base{std::cos(q.x) * reach, std::sin(q.x) * reach,
                          p.length_body_a_m + p.length_body_b_m * std::cos(q.y) - p.length_body_c_m * std::cos(q.z)};
    return base - p.workspace_origin_m;
}

glm::dmat3 woodenhaptics_jacobian(const WoodenHapticsProfile& p, glm::dvec3 q) {
    const double lb = p.length_body_b_m;
    const double lc = p.length_body_c_m;
    const double reach = lb * std::sin(q.y) + lc * std::sin(q.z);
    const double ca = std::cos(q.x);
    const double sa = std::sin(q.x);
    // glm is column-major: one column per joint.
    return glm::dmat3{glm::dvec3{-sa * reach, ca * reach, 0.0},
                      glm::dvec3{lb * ca * std::cos(q.y), lb * sa * std::cos(q.y), -lb * std::sin(q.y)},
                      glm::dvec3{lc * ca * std::cos(q.z), lc * sa * std::cos(q.z), lc * std::sin(q.z)}};
}

glm::dvec3 woodenhaptics_joint_torques(const WoodenHapticsProfile& p, glm::dvec3 q, glm::dvec3 force_n) {
    // Virtual work: tau . dq = F . dx = F . J dq for every dq, so tau = J^T F.
    return glm::transpose(woodenhaptics_jacobian(p, q)) * force_n;
}

std::array<double, 3> woodenhaptics_currents(const WoodenHapticsProfile& p, glm::dvec3 q, glm::dvec3 force_n) {
    const glm::dvec3 tau = woodenhaptics_joint_torques(p, q, force_n);
    std::array<double, 3> mA{};
    for (std::size_t i = 0; i < 3; ++i) {
        // Virtual work again, across the cable: the motor's torque (in its encoder's direction) times
        // its turn equals the joint's torque times the joint's turn.
        const double motor_nm = tau[static_cast<glm::length_t>(i)] * joint_per_motor(p, i);
        mA[i] = 1000.0 * woodenhaptics_current_direction[i] * motor_nm / p.torque_constant_nm_per_a[i];
    }
    return mA;
}

WoodenHapticsDevice::WoodenHapticsDevice(std::unique_ptr<HidTransport> transport, WoodenHapticsProfile profile)
    : transport_(std::move(transport)), profile_(std::move(profile)) {
    caps_.name = profile_.name;
    caps_.has_force_output = true;
    caps_.max_force_n = profile_.max_force_n;
    caps_.workspace_half_extent_m = glm::dvec3{profile_.workspace_radius_m};
    caps_.reports_position = true;
    caps_.silent_after_us = static_cast<std::int64_t>(profile_.silent_after_ms * 1000.0);
    caps_.max_stiffness_n_per_m = profile_.max_stiffness_n_per_m;
    caps_.max_damping_ns_per_m = profile_.max_damping_ns_per_m;
    angles_ = woodenhaptics_angles(profile_, counts_);
}

WoodenHapticsDevice::~WoodenHapticsDevice() { (void)zero_force(); }

Result<DeviceSample> WoodenHapticsDevice::poll(std::int64_t now_us) {
    // Larger than a report, so an oversized one is seen as such rather than cut to size.
    std::array<std::uint8_t, 64> buffer{};
    for (int i = 0; i < max_reports_per_poll; ++i) {
        auto n = transport_->read(buffer, 0);
        if (!n) return std::move(n).error();
        if (*n == 0) break;
        const auto counts = decode_woodenhaptics_report(std::span<const std::uint8_t>(buffer.data(), *n));
        if (!counts) {
            ++refused_;
            continue;
        }
        counts_ = *counts;
        report_us_ = now_us;
    }
    // Until the first report, the device counts as having reported when it was first polled (its
    // silence is measured from there).
    if (report_us_ == std::numeric_limits<std::int64_t>::min()) report_us_ = now_us;
    angles_ = woodenhaptics_angles(profile_, counts_);
    DeviceSample s;
    s.time_us = now_us;
    s.report_us = report_us_;
    s.position = woodenhaptics_to_device_frame(woodenhaptics_position(profile_, angles_));
    return s;
}

Result<void> WoodenHapticsDevice::send_force(glm::dvec3 force_n) {
    const auto bytes = encode_woodenhaptics_currents(woodenhaptics_currents(profile_, angles_, device_to_woodenhaptics_frame(force_n)));
    return write(bytes);
}

Result<void> WoodenHapticsDevice::zero_force() { return write(encode_woodenhaptics_currents({0.0, 0.0, 0.0})); }

Result<void> WoodenHapticsDevice::write(std::span<const std::uint8_t> report) {
    // Only the write itself is held: the report is made before, so the watchdog's zero never waits on
    // the kinematics.
    const std::lock_guard lock(write_mutex_);
    return transport_->write(report);
}

} // namespace ikebana::devices
