#pragma once
// The raw-HID protocol of the do-it-yourself force-feedback device (docs/diy-haptic-protocol.md is the
// firmware author's reference). Both directions are 32-byte reports ending in a CRC-8; every report
// carries a sequence number; the device zeroes its force by itself when no valid force report
// arrives within the watchdog time the host asked for.
#include <array>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "engine/core/result.hpp"

namespace ikebana::devices::diy {

inline constexpr std::size_t report_size = 32;
inline constexpr std::uint8_t state_report_id = 0x10;  // device -> host
inline constexpr std::uint8_t force_report_id = 0x20;  // host -> device
inline constexpr std::uint8_t protocol_version = 1;

namespace status {
inline constexpr std::uint8_t motors_enabled = 1u << 0;
inline constexpr std::uint8_t watchdog_tripped = 1u << 1;
inline constexpr std::uint8_t over_temperature = 1u << 2;
inline constexpr std::uint8_t force_clamped = 1u << 3;
} // namespace status

struct StateReport {
    std::uint16_t sequence;
    std::uint16_t acknowledged;   // sequence of the last valid force report the device accepted
    glm::ivec3 position_um;       // handle position, micrometres, in the device's frame
    glm::i16vec3 rotation_mrad;   // roll, pitch, yaw (0 on a 3-DoF device)
    std::uint16_t buttons;
    std::uint8_t status;
    double max_force_n;           // the device's own limit (sent in 0.1 N)
};

struct ForceReport {
    std::uint16_t sequence;
    glm::dvec3 force_n;           // sent in millinewtons, saturated to +-32.767 N
    bool enable_motors;
    std::uint8_t watchdog_ms;     // 1..255; the device zeroes its force after this much silence
};

std::uint8_t crc8(std::span<const std::uint8_t> bytes);

// Why a report was refused, without words: what the 1 kHz thread counts (words allocate).
enum class FrameFault : std::uint8_t { none, wrong_size, wrong_id, wrong_version, bad_crc };

// Decoding refuses, with the reason: a wrong length (truncated or oversized), another report id, an
// unknown version, a CRC mismatch.
Result<StateReport> decode_state(std::span<const std::uint8_t> bytes);
// The same check without words and without allocating, for the 1 kHz thread: fills `out` when none.
FrameFault decode_state(std::span<const std::uint8_t> bytes, StateReport& out) noexcept;
Result<ForceReport> decode_force(std::span<const std::uint8_t> bytes);
std::array<std::uint8_t, report_size> encode_state(const StateReport& report);
std::array<std::uint8_t, report_size> encode_force(const ForceReport& report);

// Sequence bookkeeping for the host: refuses reports that are not newer than the last one (replays,
// reordering) and counts the reports lost in between.
class SequenceTracker {
public:
    // True if `sequence` is newer (mod 2^16, within half the range) than the last accepted one.
    bool accept(std::uint16_t sequence);
    [[nodiscard]] std::uint64_t lost() const noexcept { return lost_; }
    [[nodiscard]] std::uint64_t refused() const noexcept { return refused_; }

private:
    bool started_ = false;
    std::uint16_t last_ = 0;
    std::uint64_t lost_ = 0;
    std::uint64_t refused_ = 0;
};

} // namespace ikebana::devices::diy
