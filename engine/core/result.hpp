#pragma once
// Recoverable failures are values, not exits (as vk-bootstrap does it): a Result carries either the
// value or an Error with a code a caller can branch on and a message a person can act on.
#include <cassert>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace ikebana {

enum class ErrorCode {
    invalid_argument,  // a value from the command line, a scene or a config that is out of range
    not_found,         // a file, a system name, a species id that does not exist
    parse_error,       // a file that exists but cannot be read as what it claims to be
    schedule_conflict, // systems that write the same data with no order between them
    io_error,          // the operating system refused a read or write
    device_error,      // a device (Vulkan, HID) is missing or misbehaves
    device_silent,     // a force device is plugged in but has sent no report for longer than its limit
    device_lost,       // a force device stopped taking forces (writes failed again and again)
    busy,              // a shared file another process holds for now (a database mid-write): try again later
};

struct Error {
    ErrorCode code;
    std::string message;
    // Text with static storage, for errors made on the 1 kHz thread: a std::string longer than its
    // small buffer allocates, and glibc's allocator locks do not inherit priority. `message` stays
    // empty there; text() gives whichever is set.
    const char* static_text = nullptr;
    [[nodiscard]] std::string_view text() const noexcept {
        return message.empty() && static_text ? std::string_view(static_text) : std::string_view(message);
    }
};

template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : state_(std::move(value)) {}
    Result(Error error) : state_(std::move(error)) {}

    [[nodiscard]] bool ok() const noexcept { return state_.index() == 0; }
    explicit operator bool() const noexcept { return ok(); }

    [[nodiscard]] T& value() & { assert(ok()); return std::get<0>(state_); }
    [[nodiscard]] const T& value() const& { assert(ok()); return std::get<0>(state_); }
    [[nodiscard]] T&& value() && { assert(ok()); return std::get<0>(std::move(state_)); }
    [[nodiscard]] const Error& error() const& { assert(!ok()); return std::get<1>(state_); }
    [[nodiscard]] Error&& error() && { assert(!ok()); return std::get<1>(std::move(state_)); }

    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

private:
    std::variant<T, Error> state_;
};

// Result<void> for operations that only succeed or fail.
struct Ok {};

template <>
class [[nodiscard]] Result<void> {
public:
    Result() = default;
    Result(Ok) {}
    Result(Error error) : error_(std::move(error)), failed_(true) {}

    [[nodiscard]] bool ok() const noexcept { return !failed_; }
    explicit operator bool() const noexcept { return ok(); }
    [[nodiscard]] const Error& error() const& { assert(failed_); return error_; }
    [[nodiscard]] Error&& error() && { assert(failed_); return std::move(error_); }

private:
    Error error_{};
    bool failed_ = false;
};

inline Error make_error(ErrorCode code, std::string message) { return Error{code, std::move(message)}; }
// An error that allocates nothing (see Error::static_text): for code on the 1 kHz thread.
inline Error lane_error(ErrorCode code, const char* static_text) noexcept { return Error{code, {}, static_text}; }

} // namespace ikebana
