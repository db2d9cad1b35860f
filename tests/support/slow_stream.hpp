#pragma once
// A stream as slow as a stalled disk or a network share: every write and every flush takes `delay`.
// What reached it is kept for the test to read (under a lock: the writer is another thread).
#include <chrono>
#include <mutex>
#include <ostream>
#include <streambuf>
#include <string>
#include <thread>

namespace ikebana::test {

class SlowStream {
public:
    explicit SlowStream(std::chrono::milliseconds delay) : buffer_(*this, delay), stream(&buffer_) {}
    [[nodiscard]] std::string text() const {
        const std::lock_guard lock(mutex_);
        return text_;
    }

private:
    class Buffer final : public std::streambuf {
    public:
        Buffer(SlowStream& owner, std::chrono::milliseconds delay) : owner_(owner), delay_(delay) {}

    protected:
        std::streamsize xsputn(const char* s, std::streamsize n) override {
            std::this_thread::sleep_for(delay_);
            const std::lock_guard lock(owner_.mutex_);
            owner_.text_.append(s, static_cast<std::size_t>(n));
            return n;
        }
        int_type overflow(int_type c) override {
            if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
            const char ch = traits_type::to_char_type(c);
            return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
        }
        int sync() override {
            std::this_thread::sleep_for(delay_);
            return 0;
        }

    private:
        SlowStream& owner_;
        std::chrono::milliseconds delay_;
    };

    mutable std::mutex mutex_;
    std::string text_;
    Buffer buffer_;

public:
    std::ostream stream;
};

} // namespace ikebana::test
