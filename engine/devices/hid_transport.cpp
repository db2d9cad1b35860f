#include "engine/devices/hid_transport.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <ctime>
#include <mutex>
#include <thread>

#include <hidapi/hidapi.h>
#include <pthread.h>
#include <semaphore.h>

#include "engine/core/monotonic_clock.hpp"
#include "engine/core/spsc_ring.hpp"
#include "engine/sched/triple_buffer.hpp"

namespace ikebana::devices {

namespace {

std::string narrow(const wchar_t* text) {
    std::string out;
    if (!text) return out;
    for (; *text; ++text) out += *text < 128 ? static_cast<char>(*text) : '?';
    return out;
}

// hidapi's enumerate, open and close call hid_init, which frees and sets a global error string with no
// lock (hidapi 0.13): two reconnecting devices' opener threads, or one of them and the main thread,
// must not be in them at once. The 1 kHz thread never takes this lock: it never calls hidapi at all.
std::mutex& bus_mutex() {
    static std::mutex m;
    return m;
}

Result<void> init_once() {
    static std::once_flag once;
    static int status = 0;
    std::call_once(once, [] { status = hid_init(); });
    if (status != 0) return make_error(ErrorCode::device_error, "hidapi could not be initialised");
    return {};
}

timespec monotonic_in(std::chrono::nanoseconds from_now) {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    const std::int64_t ns = t.tv_nsec + from_now.count();
    t.tv_sec += static_cast<time_t>(ns / 1'000'000'000);
    t.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    return t;
}

// Waits on `s` until it is posted or `wait` has passed; true if it was posted.
bool wait_for(sem_t& s, std::chrono::nanoseconds wait) {
    const timespec until = monotonic_in(wait);
    for (;;) {
        if (sem_clockwait(&s, CLOCK_MONOTONIC, &until) == 0) return true;
        if (errno != EINTR) return false;
    }
}

constexpr std::size_t max_report_bytes = 64;

struct OutReport {
    std::array<std::uint8_t, max_report_bytes> bytes{};
    std::size_t size = 0;
    std::uint64_t ticket = 0; // its number among the reports write() was given
};
struct InReport {
    std::array<std::uint8_t, max_report_bytes> bytes{};
    std::size_t size = 0;
};

// Everything the I/O thread uses. Shared, so that a thread whose last write is stuck in the kernel can
// outlive its transport (it closes the handle when the write returns) without using freed memory.
struct Link {
    static constexpr std::size_t inbound_reports = 64; // 64 ms of a device reporting every millisecond
    static constexpr int reads_per_wake = 32;
    static constexpr auto idle_wake = std::chrono::microseconds(500);

    Link(const HidApi& a, void* h, std::string p, HidTransportOptions o) : api(a), handle(h), path(std::move(p)), options(std::move(o)) {
        sem_init(&wake, 0, 0);
        sem_init(&done, 0, 0);
    }
    ~Link() {
        sem_destroy(&wake);
        sem_destroy(&done);
    }
    Link(const Link&) = delete;
    Link& operator=(const Link&) = delete;

    HidApi api;
    void* handle;
    std::string path;
    HidTransportOptions options;
    // The caller's side: the 1 kHz thread and the watchdog may both write, so two mailboxes, each
    // taken by one writer at a time through an atomic flag (never a lock: a writer that finds one taken
    // uses the other, and only two threads ever write). Tickets number the reports across both; the
    // I/O thread writes the newest ticket it has not yet written.
    struct Mailbox {
        std::atomic<bool> taken{false};
        sched::TripleBuffer<OutReport> reports;
    };
    std::array<Mailbox, 2> mailboxes;
    std::atomic<std::uint64_t> next_ticket{0};
    std::uint64_t last_ticket_written = 0; // the I/O thread's own
    std::atomic<std::uint64_t> queued_seen{0};
    std::atomic<std::uint64_t> written{0};
    SpscRing<InReport> inbound{inbound_reports};
    std::atomic<std::uint64_t> inbound_dropped{0};
    std::atomic<bool> read_failed{false};
    std::atomic<bool> write_failed{false};
    std::atomic<std::int64_t> writing_since_ns{0};
    std::atomic<IoPriority> priority{IoPriority::normal};
    std::atomic<bool> stop{false};
    sem_t wake{};
    sem_t done{};
};

void write_newest(Link& link) {
    const OutReport* newest = nullptr;
    for (auto& box : link.mailboxes) {
        (void)box.reports.update();
        const OutReport& r = box.reports.read_buffer();
        if (r.ticket > link.last_ticket_written && (newest == nullptr || r.ticket > newest->ticket)) newest = &r;
    }
    if (newest == nullptr) return;
    link.last_ticket_written = newest->ticket;
    link.writing_since_ns.store(monotonic_ns(), std::memory_order_release);
    const int n = link.api.write(link.handle, newest->bytes.data(), newest->size);
    link.writing_since_ns.store(0, std::memory_order_release);
    if (n < 0) {
        link.write_failed.store(true, std::memory_order_release);
    } else {
        link.written.store(newest->ticket, std::memory_order_release);
    }
}

void read_available(Link& link) {
    if (link.read_failed.load(std::memory_order_relaxed)) return;
    for (int i = 0; i < Link::reads_per_wake; ++i) {
        InReport* slot = link.inbound.claim();
        InReport overflow;
        InReport& into = slot ? *slot : overflow;
        const int n = link.api.read_timeout(link.handle, into.bytes.data(), into.bytes.size(), 0);
        if (n < 0) {
            link.read_failed.store(true, std::memory_order_release);
            return;
        }
        if (n == 0) return;
        if (!slot) {
            // The reader has stopped taking reports (a stalled lane): the newest is dropped, counted.
            link.inbound_dropped.fetch_add(1, std::memory_order_relaxed);
            continue;
        }
        into.size = static_cast<std::size_t>(n);
        link.inbound.commit();
    }
}

void io_loop(const std::shared_ptr<Link>& link) {
    pthread_setname_np(pthread_self(), "ikebana-hid-io");
    if (link->options.fifo_priority > 0) {
        sched_param param{};
        param.sched_priority = link->options.fifo_priority;
        link->priority.store(pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0 ? IoPriority::realtime : IoPriority::not_permitted);
    }
    for (;;) {
        // Stop is looked at before the mailbox: whatever was queued before the stop (the zero a chain
        // queues as it ends) is written below, after it.
        const bool stopping = link->stop.load(std::memory_order_acquire);
        write_newest(*link);
        if (stopping) break;
        read_available(*link);
        (void)wait_for(link->wake, Link::idle_wake);
        while (sem_trywait(&link->wake) == 0) {} // several posts since: one look serves them all
    }
    {
        const std::lock_guard lock(bus_mutex());
        link->api.close(link->handle);
    }
    sem_post(&link->done);
}

class HidapiTransport final : public HidTransport {
public:
    static constexpr auto stalled_after = std::chrono::milliseconds(20);

    HidapiTransport(const HidApi& api, void* handle, std::string path, HidTransportOptions options)
        : link_(std::make_shared<Link>(api, handle, std::move(path), std::move(options))), io_([link = link_] { io_loop(link); }) {}

    ~HidapiTransport() override {
        link_->stop.store(true, std::memory_order_release);
        sem_post(&link_->wake);
        if (wait_for(link_->done, link_->options.close_wait)) {
            io_.join();
            return;
        }
        // Stuck in the kernel (a hung hub): the program does not wait for it. The thread closes the
        // handle when the write returns; the device's own watchdog zeroes it meanwhile.
        char line[256];
        std::snprintf(line, sizeof line, "%s: the last report has waited for the device for over %lld ms; it is left to its own watchdog",
                      link_->path.c_str(), static_cast<long long>(link_->options.close_wait.count()));
        if (link_->options.say) {
            link_->options.say(line);
        } else {
            std::fprintf(stderr, "ikebana: %s\n", line);
        }
        io_.detach();
    }
    HidapiTransport(const HidapiTransport&) = delete;
    HidapiTransport& operator=(const HidapiTransport&) = delete;

    Result<std::size_t> read(std::span<std::uint8_t> buffer, int timeout_ms) override {
        const std::int64_t until_ns = monotonic_ns() + std::int64_t{timeout_ms} * 1'000'000;
        for (;;) {
            if (const InReport* in = link_->inbound.peek()) {
                const std::size_t n = std::min(in->size, buffer.size());
                std::copy_n(in->bytes.begin(), n, buffer.begin());
                link_->inbound.release();
                return n;
            }
            if (link_->read_failed.load(std::memory_order_acquire)) return lane_error(ErrorCode::device_error, "a read from the device failed (unplugged?)");
            if (timeout_ms <= 0 || monotonic_ns() >= until_ns) return std::size_t{0};
            std::this_thread::sleep_for(std::chrono::microseconds(100)); // off the 1 kHz thread only (it asks with 0)
        }
    }

    Result<void> write(std::span<const std::uint8_t> report) override {
        if (report.size() > max_report_bytes) return lane_error(ErrorCode::invalid_argument, "a report longer than 64 bytes");
        queue(report);
        sem_post(&link_->wake);
        if (link_->write_failed.exchange(false, std::memory_order_acq_rel)) {
            return lane_error(ErrorCode::device_error, "a write to the device failed (unplugged?)");
        }
        const std::int64_t since = link_->writing_since_ns.load(std::memory_order_acquire);
        if (since != 0 && monotonic_ns() - since > std::chrono::nanoseconds(stalled_after).count()) {
            return lane_error(ErrorCode::device_error, "a write has been waiting for the device for over 20 ms");
        }
        return {};
    }

    [[nodiscard]] WireCounts wire() const override {
        return {link_->queued_seen.load(std::memory_order_acquire), link_->written.load(std::memory_order_acquire), this};
    }
    [[nodiscard]] IoPriority io_priority() const override { return link_->priority.load(); }

private:
    // Copies the report into a free mailbox. Spins only while both are taken, which needs a third
    // writer at once (there are two: the lane and the watchdog); each holds one for a 64-byte copy.
    void queue(std::span<const std::uint8_t> report) noexcept {
        for (std::size_t i = 0;; i = (i + 1) % link_->mailboxes.size()) {
            Link::Mailbox& box = link_->mailboxes[i];
            if (box.taken.exchange(true, std::memory_order_acquire)) continue;
            OutReport& r = box.reports.write_buffer();
            std::copy(report.begin(), report.end(), r.bytes.begin());
            r.size = report.size();
            const std::uint64_t ticket = link_->next_ticket.fetch_add(1, std::memory_order_relaxed) + 1;
            r.ticket = ticket;
            box.reports.publish();
            box.taken.store(false, std::memory_order_release);
            std::uint64_t seen = link_->queued_seen.load(std::memory_order_relaxed);
            while (seen < ticket && !link_->queued_seen.compare_exchange_weak(seen, ticket, std::memory_order_acq_rel)) {}
            return;
        }
    }

    std::shared_ptr<Link> link_;
    std::thread io_; // last: it starts when everything it uses is there
};

int real_read(void* handle, unsigned char* data, std::size_t length, int milliseconds) {
    return hid_read_timeout(static_cast<hid_device*>(handle), data, length, milliseconds);
}
int real_write(void* handle, const unsigned char* data, std::size_t length) { return hid_write(static_cast<hid_device*>(handle), data, length); }
void real_close(void* handle) { hid_close(static_cast<hid_device*>(handle)); }

} // namespace

const HidApi& real_hidapi() {
    static const HidApi api{real_read, real_write, real_close};
    return api;
}

std::unique_ptr<HidTransport> make_hidapi_transport(const HidApi& api, void* handle, std::string path, HidTransportOptions options) {
    return std::make_unique<HidapiTransport>(api, handle, std::move(path), std::move(options));
}

Result<std::vector<HidDeviceInfo>> enumerate_hid_devices() {
    const std::lock_guard lock(bus_mutex());
    if (auto ok = init_once(); !ok) return std::move(ok).error();
    std::vector<HidDeviceInfo> out;
    hid_device_info* list = hid_enumerate(0, 0);
    for (hid_device_info* d = list; d; d = d->next) {
        out.push_back({d->vendor_id, d->product_id, d->path ? d->path : "", narrow(d->manufacturer_string), narrow(d->product_string)});
    }
    hid_free_enumeration(list);
    return out;
}

Result<std::unique_ptr<HidTransport>> open_hid_device(const std::string& path) {
    hid_device* device = nullptr;
    {
        const std::lock_guard lock(bus_mutex());
        if (auto ok = init_once(); !ok) return std::move(ok).error();
        device = hid_open_path(path.c_str());
    }
    if (!device) return make_error(ErrorCode::device_error, path + ": cannot be opened (permissions? see docs/haptics.md, 'Checking it')");
    return make_hidapi_transport(real_hidapi(), device, path);
}

} // namespace ikebana::devices
