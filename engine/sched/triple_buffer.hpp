#pragma once
// The one way data crosses between the haptic thread and the main thread: a triple-buffered snapshot.
// The writer never waits for the reader and the reader never waits for the writer; the reader always
// gets the newest complete snapshot (or keeps the one it has). One writer thread, one reader thread.
#include <array>
#include <atomic>
#include <cstdint>

namespace ikebana::sched {

template <typename T>
class TripleBuffer {
public:
    TripleBuffer() = default;
    explicit TripleBuffer(const T& initial) : slots_{initial, initial, initial} {}

    // Writer side: fill write_buffer(), then publish().
    [[nodiscard]] T& write_buffer() noexcept { return slots_[back_]; }
    void publish() noexcept {
        const std::uint8_t previous = middle_.exchange(static_cast<std::uint8_t>(back_ | fresh_bit), std::memory_order_acq_rel);
        back_ = previous & index_mask;
    }

    // Reader side: take the newest published snapshot if there is one; returns whether it changed.
    bool update() noexcept {
        if ((middle_.load(std::memory_order_relaxed) & fresh_bit) == 0) return false;
        const std::uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
        front_ = previous & index_mask;
        return true;
    }
    [[nodiscard]] const T& read_buffer() const noexcept { return slots_[front_]; }

    // Its three snapshots and which is whose, copied aside (a replay's saved moment), and taken in
    // (which cannot fail). Only while neither side runs: the one thread that drives a deterministic clock.
    struct Copy {
        std::array<T, 3> slots;
        std::uint8_t back = 0, front = 1, middle = 2;
    };
    [[nodiscard]] Copy copy() const { return Copy{slots_, back_, front_, middle_.load(std::memory_order_relaxed)}; }
    void take(Copy&& c) noexcept {
        slots_.swap(c.slots);
        back_ = c.back;
        front_ = c.front;
        middle_.store(c.middle, std::memory_order_relaxed);
    }

private:
    static constexpr std::uint8_t index_mask = 0x3;
    static constexpr std::uint8_t fresh_bit = 0x4;

    std::array<T, 3> slots_{};
    std::uint8_t back_ = 0;            // writer-owned
    std::uint8_t front_ = 1;           // reader-owned
    std::atomic<std::uint8_t> middle_{2}; // shared: index plus "fresh" flag
};

} // namespace ikebana::sched
