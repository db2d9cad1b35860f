#include "engine/core/emergency_stop.hpp"

#include <array>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

#include "engine/core/monotonic_clock.hpp"

namespace ikebana {

namespace {

struct Registry {
    std::mutex mutex; // try_lock in a loop where bounded (a timed_mutex's clocklock is unseen by TSan)
    std::array<EmergencyStop, emergency_slots> slots{};
};

Registry& registry() {
    static Registry r; // never destroyed before a device that registered: devices unregister first
    return r;
}

std::atomic<int> asked_by{0};
std::atomic<bool> asked{false};
std::atomic<std::int64_t> asked_at_ns{0};
// A signal again within this long is the same request: `timeout`, and a kill of a process group,
// send one to the child and one to its group, and the child gets both.
constexpr std::int64_t same_request_ns = 2'000'000'000;

extern "C" void on_stop_signal(int signal_number) {
    const std::int64_t now = monotonic_ns(); // clock_gettime: async-signal-safe
    if (asked.exchange(true)) {
        if (now - asked_at_ns.load() < same_request_ns) return;
        // Asked again later (the program did not end): at once. The devices' own watchdogs zero them
        // (2 ms for the DIY firmware).
        std::signal(signal_number, SIG_DFL);
        std::raise(signal_number);
        return;
    }
    asked_at_ns.store(now);
    asked_by.store(signal_number);
}

[[noreturn]] void on_terminate() noexcept {
    const std::size_t stopped = run_emergency_stops();
    const char* what = "no exception";
    std::string text;
    if (const std::exception_ptr current = std::current_exception()) {
        try {
            std::rethrow_exception(current);
        } catch (const std::exception& e) {
            text = e.what();
            what = text.c_str();
        } catch (...) {
            what = "an exception of unknown type";
        }
    }
    std::fprintf(stderr, "ikebana: ended by std::terminate (%s); %zu pushing device(s) sent zero force\n", what, stopped);
    std::abort();
}

} // namespace

std::size_t add_emergency_stop(EmergencyStop stop) noexcept {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    for (std::size_t i = 0; i < r.slots.size(); ++i) {
        if (!r.slots[i].stop) {
            r.slots[i] = stop;
            return i;
        }
    }
    return no_emergency_slot;
}

void remove_emergency_stop(std::size_t slot) noexcept {
    if (slot >= emergency_slots) return;
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    r.slots[slot] = {};
}

std::size_t run_emergency_stops(std::chrono::milliseconds wait) noexcept {
    Registry& r = registry();
    // Bounded: a thread that died holding the lock (it never throws there) must not hang the way out.
    bool locked = r.mutex.try_lock();
    for (int i = 0; i < 100 && !locked; ++i) {
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        locked = r.mutex.try_lock();
    }
    std::size_t stopped = 0;
    for (const auto& s : r.slots) {
        if (!s.stop) continue;
        s.stop(s.context);
        ++stopped;
    }
    const std::int64_t until = monotonic_ns() + std::chrono::nanoseconds(wait).count();
    for (const auto& s : r.slots) {
        if (!s.stop || !s.flushed) continue;
        while (!s.flushed(s.context) && monotonic_ns() < until) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (locked) r.mutex.unlock();
    return stopped;
}

void install_stop_signals() noexcept {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

bool stop_requested() noexcept { return asked.load(std::memory_order_relaxed) && asked_by.load(std::memory_order_relaxed) != 0; }
int stop_signal() noexcept { return asked_by.load(std::memory_order_relaxed); }
void request_stop(int signal_number) noexcept {
    asked_by.store(signal_number);
    asked.store(true);
}
void clear_stop_request() noexcept {
    asked_by.store(0);
    asked.store(false);
}

void install_terminate_handler() noexcept { std::set_terminate(on_terminate); }

} // namespace ikebana
