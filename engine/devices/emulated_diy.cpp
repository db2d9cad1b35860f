#include "engine/devices/emulated_diy.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

#include "engine/core/monotonic_clock.hpp"
#include "engine/devices/diy_protocol.hpp"

namespace ikebana::devices {

namespace {

struct Emulated {
    int log = -1;
    std::int64_t opened_ns = 0;
    std::int64_t next_report_ns = 0;
    std::uint16_t sequence = 0;
    std::uint16_t acknowledged = 0;
};

// Called by the transport's own thread only, one call at a time (as hidapi is).
int emulated_read(void* handle, unsigned char* data, std::size_t length, int) {
    auto& e = *static_cast<Emulated*>(handle);
    const std::int64_t now = monotonic_ns();
    if (now < e.next_report_ns || length < diy::report_size) return 0;
    // Every millisecond, as the firmware does; after a pause it does not make up the reports it missed.
    e.next_report_ns = std::max(e.next_report_ns + 1'000'000, now);
    diy::StateReport r{};
    r.sequence = ++e.sequence;
    r.acknowledged = e.acknowledged;
    r.status = diy::status::motors_enabled;
    r.max_force_n = 3.0;
    // A hand on the handle: held 60 mm above the centre for half a second (the chain engages while
    // nothing is touched), then sinking over a second to 20 mm below it, where a hand resting on the
    // handle presses whatever is there (the table, the kenzan's plate) and feels it push back.
    const double seconds = static_cast<double>(now - e.opened_ns) * 1e-9;
    const double sink = std::clamp(seconds - 0.5, 0.0, 1.0);
    r.position_um = glm::ivec3{0, 0, static_cast<int>(std::lround(60'000.0 - 80'000.0 * sink))};
    const auto bytes = diy::encode_state(r);
    std::memcpy(data, bytes.data(), bytes.size());
    return static_cast<int>(bytes.size());
}

int emulated_write(void* handle, const unsigned char* data, std::size_t length) {
    auto& e = *static_cast<Emulated*>(handle);
    const auto report = diy::decode_force(std::span<const std::uint8_t>(data, length));
    char line[96];
    int n = 0;
    if (report) {
        e.acknowledged = report->sequence;
        n = std::snprintf(line, sizeof line, "force %.6f %.6f %.6f\n", report->force_n.x, report->force_n.y, report->force_n.z);
    } else {
        n = std::snprintf(line, sizeof line, "refused\n");
    }
    if (::write(e.log, line, static_cast<std::size_t>(n)) != n) return -1;
    return static_cast<int>(length);
}

void emulated_close(void* handle) {
    auto* e = static_cast<Emulated*>(handle);
    ::close(e->log);
    delete e;
}

const HidApi emulated_api{emulated_read, emulated_write, emulated_close};

} // namespace

Result<std::unique_ptr<HidTransport>> open_emulated_diy(const std::string& log_path) {
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) return make_error(ErrorCode::io_error, log_path + ": cannot be written (" + std::strerror(errno) + ")");
    auto* e = new Emulated{};
    e->log = fd;
    e->opened_ns = monotonic_ns();
    return make_hidapi_transport(emulated_api, e, "emulated DIY device (" + log_path + ")");
}

} // namespace ikebana::devices
