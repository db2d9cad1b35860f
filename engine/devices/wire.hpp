#pragma once
// What a device's transport says of the bytes it moves, for the HUD and --stats: which reports reached
// the wire, and how its I/O thread is scheduled. Plain values, safe to copy across threads.
#include <cstdint>

namespace ikebana::devices {

// Where a transport's reports stand: how many write() has queued and which of them last reached the
// device (numbered 1, 2, ... in the order write() was called). A report replaced in the mailbox by a
// newer one before it was sent is never written. A synchronous transport (a test's fake) writes
// what it is given at once: written == queued.
struct WireCounts {
    std::uint64_t queued = 0;
    std::uint64_t written = 0;
    const void* transport = nullptr; // which transport counted (a reconnected device starts again at 0)
};

// The priority of a transport's own I/O thread, as the system granted it.
enum class IoPriority : std::uint8_t {
    none,          // no thread of its own (a synchronous transport)
    realtime,      // SCHED_FIFO, as asked
    normal,        // normal scheduling was asked for
    not_permitted, // SCHED_FIFO was asked for and refused (no CAP_SYS_NICE, no rtprio limit)
};

} // namespace ikebana::devices
