#pragma once
// Whatever way the program ends, nothing goes on pushing on a person's hand. Every device that pushes
// registers a stop here (SafeForceDevice does, as it is made); the ways out that skip the ordinary
// unwinding call them all:
//  - an exception on a real-time lane (RealtimeClock catches it, runs the stops, ends the run and says
//    why in its report);
//  - std::terminate (install_terminate_handler: the stops, a line saying why, then abort);
//  - SIGINT and SIGTERM (install_stop_signals: the handler only sets a flag, as a signal handler may;
//    the clocks and the window loops see it and end the ordinary way, which zeroes every device; a
//    second signal ends the program at once, leaving the devices to their own watchdogs).
// A stop queues a zero-force report; `flushed` says whether it has reached the wire, which the
// terminate path waits for (bounded) before the process goes.
#include <chrono>
#include <cstddef>

namespace ikebana {

struct EmergencyStop {
    void (*stop)(void* context) noexcept = nullptr;
    bool (*flushed)(void* context) noexcept = nullptr; // null: nothing to wait for
    void* context = nullptr;
};

inline constexpr std::size_t no_emergency_slot = static_cast<std::size_t>(-1);
inline constexpr std::size_t emergency_slots = 64;

// Off the 1 kHz thread (they take a lock). add returns no_emergency_slot when every slot is taken.
[[nodiscard]] std::size_t add_emergency_stop(EmergencyStop stop) noexcept;
void remove_emergency_stop(std::size_t slot) noexcept;
// Runs every registered stop, then waits up to `wait` for each to be flushed; the number of stops run.
// Safe from any thread, a terminate handler's included (it takes the registry's lock for a bounded time
// only, then goes on without it).
std::size_t run_emergency_stops(std::chrono::milliseconds wait = std::chrono::milliseconds(100)) noexcept;

// SIGINT/SIGTERM: the first asks the program to stop (stop_requested()); one more, 2 s or more later,
// ends it at once.
void install_stop_signals() noexcept;
[[nodiscard]] bool stop_requested() noexcept;
[[nodiscard]] int stop_signal() noexcept; // the signal that asked, 0 if none
void request_stop(int signal_number) noexcept; // what the handler does; for tests
void clear_stop_request() noexcept;            // for tests

// std::terminate runs every stop, says on stderr that the program ended and why, and aborts.
void install_terminate_handler() noexcept;

} // namespace ikebana
