#pragma once
// A bounded queue between exactly one producer thread and one consumer thread that never blocks and
// never allocates after construction: what the 1 kHz thread may use to hand work to a slower thread (a
// writer, an opener) or to take commands from the main thread. Full: push refuses; empty: pop refuses.
#include <atomic>
#include <cstddef>
#include <memory>

namespace ikebana {

template <typename T>
class SpscRing {
public:
    // `capacity` is rounded up to a power of two.
    explicit SpscRing(std::size_t capacity) : mask_(round_up(capacity) - 1), slots_(std::make_unique<T[]>(mask_ + 1)) {}

    // Producer side.
    [[nodiscard]] bool push(const T& value) noexcept {
        const std::size_t head = head_.load(std::memory_order_relaxed);
        if (head - tail_.load(std::memory_order_acquire) > mask_) return false;
        slots_[head & mask_] = value;
        head_.store(head + 1, std::memory_order_release);
        return true;
    }
    // Producer side: the slot the next push fills, to write in place (a line of text, say); nullptr when
    // full. commit() publishes it.
    [[nodiscard]] T* claim() noexcept {
        const std::size_t head = head_.load(std::memory_order_relaxed);
        if (head - tail_.load(std::memory_order_acquire) > mask_) return nullptr;
        return &slots_[head & mask_];
    }
    void commit() noexcept { head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

    // Consumer side.
    [[nodiscard]] bool pop(T& out) noexcept {
        const T* front = peek();
        if (!front) return false;
        out = *front;
        release();
        return true;
    }
    [[nodiscard]] const T* peek() noexcept {
        const std::size_t tail = tail_.load(std::memory_order_relaxed);
        if (tail == head_.load(std::memory_order_acquire)) return nullptr;
        return &slots_[tail & mask_];
    }
    void release() noexcept { tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

    // Either side; a moment's view.
    [[nodiscard]] std::size_t size() const noexcept {
        return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
    }
    [[nodiscard]] std::size_t capacity() const noexcept { return mask_ + 1; }

private:
    static std::size_t round_up(std::size_t n) {
        std::size_t p = 1;
        while (p < n) p <<= 1;
        return p;
    }
    std::size_t mask_;
    std::unique_ptr<T[]> slots_;
    // Apart, so the producer's and the consumer's writes do not share a cache line.
    alignas(64) std::atomic<std::size_t> head_{0};
    alignas(64) std::atomic<std::size_t> tail_{0};
};

} // namespace ikebana
