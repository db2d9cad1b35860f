#pragma once
// Text written from the 1 kHz thread (a device recording, the trainee's commands, a device's comings
// and goings) reaches its file through a thread of its own: the haptic thread copies a line into a
// bounded single-producer ring and goes on; the writer thread takes the lines out, writes them and
// flushes every `flush_every` (a session cut short by a crash keeps all but its last moments). The
// producer never opens, writes, flushes, allocates or waits on a lock.
//
// When the ring is full (the writer starved for seconds): a real-time producer drops the line and it
// is counted (dropped()); a headless run, which has no deadline, waits for room instead, so that a
// recording made faster than real time is always whole.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <ostream>
#include <string>
#include <string_view>
#include <thread>

#include "engine/core/spsc_ring.hpp"

namespace ikebana {

class AsyncLineWriter {
public:
    static constexpr std::size_t max_line_bytes = 240;
    enum class WhenFull { drop, wait };

    explicit AsyncLineWriter(std::ostream& out, WhenFull when_full = WhenFull::drop, std::size_t capacity_lines = 8192,
                             std::chrono::milliseconds flush_every = std::chrono::milliseconds(100));
    // Writes everything queued, flushes, and stops the writer thread. `out` must outlive this.
    ~AsyncLineWriter();
    AsyncLineWriter(const AsyncLineWriter&) = delete;
    AsyncLineWriter& operator=(const AsyncLineWriter&) = delete;

    // From one producer thread: queues `text` (written as given: end lines with '\n'). False when it was
    // not queued: longer than max_line_bytes, or the ring full in drop mode; either is counted.
    bool write(std::string_view text) noexcept;
    // Waits until everything queued so far is written and flushed. Not for the 1 kHz thread.
    void flush();
    [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }
    // The stream refused a write or a flush (a full disk, a vanished share): from then on lines are
    // taken and thrown away (the producer never waits on a dead file), and the file is not whole.
    [[nodiscard]] bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
    // Why, in words ("No space left on device"); empty while it has not failed.
    [[nodiscard]] std::string failure() const;
    // Told once, on the writer's thread, the moment the stream fails (say it at once). Set before
    // anything is written.
    void on_failure(std::function<void(const std::string& why)> tell) { tell_ = std::move(tell); }

private:
    struct Line {
        std::uint16_t size = 0;
        char text[max_line_bytes];
    };
    void run();
    void write_queued();

    std::ostream& out_;
    WhenFull when_full_;
    std::chrono::milliseconds flush_every_;
    SpscRing<Line> ring_;
    static constexpr std::size_t batch_bytes = 1 << 16;
    std::string batch_; // the writer thread's
    std::atomic<std::uint64_t> dropped_{0};
    void note_failure(int error_number);
    std::atomic<bool> failed_{false};
    std::string failure_;                                   // set once, before failed_
    std::function<void(const std::string&)> tell_;
    std::mutex mutex_; // the writer's own wake-up; the producer never takes it
    std::condition_variable wake_;
    std::condition_variable flushed_;
    bool stop_ = false;
    std::uint64_t flush_asked_ = 0;
    std::uint64_t flush_done_ = 0;
    std::thread thread_;
};

} // namespace ikebana
