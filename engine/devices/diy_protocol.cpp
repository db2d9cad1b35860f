#include "engine/devices/diy_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace ikebana::devices::diy {

namespace {

void put16(std::uint8_t* p, std::uint16_t v) {
    p[0] = static_cast<std::uint8_t>(v & 0xff);
    p[1] = static_cast<std::uint8_t>(v >> 8);
}
void put32(std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xff);
}
std::uint16_t get16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t get32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) | (static_cast<std::uint32_t>(p[2]) << 16) |
           (static_cast<std::uint32_t>(p[3]) << 24);
}

FrameFault frame_fault(std::span<const std::uint8_t> bytes, std::uint8_t id) noexcept {
    if (bytes.size() != report_size) return FrameFault::wrong_size;
    if (bytes[0] != id) return FrameFault::wrong_id;
    if (bytes[1] != protocol_version) return FrameFault::wrong_version;
    if (crc8(bytes.first(report_size - 1)) != bytes[report_size - 1]) return FrameFault::bad_crc;
    return FrameFault::none;
}

// The reason in words, with the numbers: for a person (tests, `ikebana devices`), never the 1 kHz thread.
Result<void> check_frame(std::span<const std::uint8_t> bytes, std::uint8_t id, const char* what) {
    const std::string name = what;
    switch (frame_fault(bytes, id)) {
    case FrameFault::none: return {};
    case FrameFault::wrong_size:
        return make_error(ErrorCode::device_error, name + " report of " + std::to_string(bytes.size()) + " bytes, expected " +
                                                       std::to_string(report_size));
    case FrameFault::wrong_id: return make_error(ErrorCode::device_error, name + " report has id " + std::to_string(bytes[0]));
    case FrameFault::wrong_version:
        return make_error(ErrorCode::device_error, name + " report speaks protocol version " + std::to_string(bytes[1]) +
                                                       ", this host speaks " + std::to_string(protocol_version));
    case FrameFault::bad_crc: return make_error(ErrorCode::device_error, name + " report fails its CRC (corrupted)");
    }
    return {};
}

StateReport read_state(std::span<const std::uint8_t> b) noexcept {
    StateReport r{};
    r.sequence = get16(&b[2]);
    r.acknowledged = get16(&b[4]);
    for (int i = 0; i < 3; ++i) r.position_um[i] = static_cast<std::int32_t>(get32(&b[6 + 4 * static_cast<std::size_t>(i)]));
    for (int i = 0; i < 3; ++i) r.rotation_mrad[i] = static_cast<std::int16_t>(get16(&b[18 + 2 * static_cast<std::size_t>(i)]));
    r.buttons = get16(&b[24]);
    r.status = b[26];
    r.max_force_n = b[27] / 10.0;
    return r;
}

std::int16_t saturate16(double v) {
    if (!std::isfinite(v)) return 0;
    return static_cast<std::int16_t>(std::clamp(std::lround(v), -32767l, 32767l));
}

} // namespace

std::uint8_t crc8(std::span<const std::uint8_t> bytes) {
    // CRC-8/SMBUS: polynomial 0x07, initial 0; a few lines on any microcontroller.
    std::uint8_t crc = 0;
    for (const std::uint8_t b : bytes) {
        crc ^= b;
        for (int bit = 0; bit < 8; ++bit) crc = static_cast<std::uint8_t>((crc & 0x80) ? (crc << 1) ^ 0x07 : crc << 1);
    }
    return crc;
}

std::array<std::uint8_t, report_size> encode_state(const StateReport& r) {
    std::array<std::uint8_t, report_size> b{};
    b[0] = state_report_id;
    b[1] = protocol_version;
    put16(&b[2], r.sequence);
    put16(&b[4], r.acknowledged);
    for (int i = 0; i < 3; ++i) put32(&b[6 + 4 * static_cast<std::size_t>(i)], static_cast<std::uint32_t>(r.position_um[i]));
    for (int i = 0; i < 3; ++i) put16(&b[18 + 2 * static_cast<std::size_t>(i)], static_cast<std::uint16_t>(r.rotation_mrad[i]));
    put16(&b[24], r.buttons);
    b[26] = r.status;
    b[27] = static_cast<std::uint8_t>(std::clamp(std::lround(r.max_force_n * 10.0), 0l, 255l));
    b[31] = crc8(std::span<const std::uint8_t>(b).first(report_size - 1));
    return b;
}

Result<StateReport> decode_state(std::span<const std::uint8_t> b) {
    if (auto ok = check_frame(b, state_report_id, "state"); !ok) return std::move(ok).error();
    return read_state(b);
}

FrameFault decode_state(std::span<const std::uint8_t> b, StateReport& out) noexcept {
    const FrameFault fault = frame_fault(b, state_report_id);
    if (fault == FrameFault::none) out = read_state(b);
    return fault;
}

std::array<std::uint8_t, report_size> encode_force(const ForceReport& r) {
    std::array<std::uint8_t, report_size> b{};
    b[0] = force_report_id;
    b[1] = protocol_version;
    put16(&b[2], r.sequence);
    for (int i = 0; i < 3; ++i) {
        put16(&b[4 + 2 * static_cast<std::size_t>(i)], static_cast<std::uint16_t>(saturate16(r.force_n[i] * 1000.0)));
    }
    b[10] = r.enable_motors ? 1 : 0;
    b[11] = r.watchdog_ms == 0 ? 2 : r.watchdog_ms;
    b[31] = crc8(std::span<const std::uint8_t>(b).first(report_size - 1));
    return b;
}

Result<ForceReport> decode_force(std::span<const std::uint8_t> b) {
    if (auto ok = check_frame(b, force_report_id, "force"); !ok) return std::move(ok).error();
    ForceReport r{};
    r.sequence = get16(&b[2]);
    for (int i = 0; i < 3; ++i) r.force_n[i] = static_cast<std::int16_t>(get16(&b[4 + 2 * static_cast<std::size_t>(i)])) / 1000.0;
    r.enable_motors = (b[10] & 1) != 0;
    r.watchdog_ms = b[11];
    return r;
}

bool SequenceTracker::accept(std::uint16_t sequence) {
    if (!started_) {
        started_ = true;
        last_ = sequence;
        return true;
    }
    const auto ahead = static_cast<std::uint16_t>(sequence - last_);
    if (ahead == 0 || ahead >= 0x8000) {
        ++refused_;
        return false;
    }
    lost_ += ahead - 1u;
    last_ = sequence;
    return true;
}

} // namespace ikebana::devices::diy
