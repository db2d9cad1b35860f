#include "engine/core/async_line_writer.hpp"

#include <cerrno>
#include <cstring>

namespace ikebana {

namespace {
// The writer looks at the ring at least this often; the producer wakes it sooner when the ring fills
// up (a lost wake-up costs at most this much).
constexpr auto writer_period = std::chrono::milliseconds(10);
} // namespace

AsyncLineWriter::AsyncLineWriter(std::ostream& out, WhenFull when_full, std::size_t capacity_lines, std::chrono::milliseconds flush_every)
    : out_(out), when_full_(when_full), flush_every_(flush_every), ring_(capacity_lines) {
    batch_.reserve(batch_bytes + max_line_bytes);
    thread_ = std::thread([this] { run(); });
}

AsyncLineWriter::~AsyncLineWriter() {
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

bool AsyncLineWriter::write(std::string_view text) noexcept {
    if (text.size() > max_line_bytes) {
        dropped_.fetch_add(1, std::memory_order_relaxed);
        return false;
    }
    Line* slot = ring_.claim();
    while (!slot) {
        if (when_full_ == WhenFull::drop) {
            dropped_.fetch_add(1, std::memory_order_relaxed);
            return false;
        }
        // A headless producer has no deadline: it gives the writer the core until there is room.
        wake_.notify_one();
        std::this_thread::sleep_for(std::chrono::microseconds(100));
        slot = ring_.claim();
    }
    std::memcpy(slot->text, text.data(), text.size());
    slot->size = static_cast<std::uint16_t>(text.size());
    ring_.commit();
    // A headless producer wakes the writer at a quarter full. A real-time one never does: glibc's
    // notify takes the condition variable's internal lock, which is not priority inheriting; the
    // writer looks every 10 ms, and the ring holds seconds.
    if (when_full_ == WhenFull::wait && ring_.size() == ring_.capacity() / 4) wake_.notify_one();
    return true;
}

void AsyncLineWriter::flush() {
    std::unique_lock lock(mutex_);
    const std::uint64_t ticket = ++flush_asked_;
    wake_.notify_one();
    flushed_.wait(lock, [&] { return flush_done_ >= ticket; });
}

std::string AsyncLineWriter::failure() const { return failed() ? failure_ : std::string(); }

void AsyncLineWriter::note_failure(int error_number) {
    if (failed()) return;
    failure_ = error_number != 0 ? std::strerror(error_number) : "the file refused a write";
    failed_.store(true, std::memory_order_release);
    if (tell_) tell_(failure_);
}

void AsyncLineWriter::write_queued() {
    // In one write per batch: a slow stream (a network share) pays its cost once, not once a line.
    batch_.clear();
    const auto put = [&] {
        if (failed()) return; // a dead file: the lines go nowhere, the producer goes on
        errno = 0;
        out_.write(batch_.data(), static_cast<std::streamsize>(batch_.size()));
        if (!out_) note_failure(errno);
    };
    while (const Line* line = ring_.peek()) {
        batch_.append(line->text, line->size);
        ring_.release();
        if (batch_.size() >= batch_bytes) {
            put();
            batch_.clear();
        }
    }
    if (!batch_.empty()) put();
}

void AsyncLineWriter::run() {
    auto last_flush = std::chrono::steady_clock::now();
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait_for(lock, writer_period, [&] { return stop_ || flush_asked_ > flush_done_ || ring_.size() >= ring_.capacity() / 4; });
        const bool stopping = stop_;
        const std::uint64_t asked = flush_asked_;
        lock.unlock();
        write_queued();
        const auto now = std::chrono::steady_clock::now();
        if ((stopping || asked > flush_done_ || now - last_flush >= flush_every_) && !failed()) {
            errno = 0;
            out_.flush();
            if (!out_) note_failure(errno);
            last_flush = now;
        }
        lock.lock();
        if (asked > flush_done_) {
            flush_done_ = asked;
            flushed_.notify_all();
        }
        if (stopping && ring_.size() == 0) return;
    }
}

} // namespace ikebana
