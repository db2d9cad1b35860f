#pragma once
// A small dense integer per type, the same in every registry: indexes component storages, and the
// access masks the scheduler checks systems against (resources are numbered the same way).
#include <atomic>
#include <cstdint>
#include <type_traits>

namespace ikebana::ecs {

namespace detail {
inline std::atomic<std::uint32_t> next_type_id{0};
template <typename T>
std::uint32_t type_id_of() {
    static const std::uint32_t id = next_type_id.fetch_add(1);
    return id;
}
} // namespace detail

// const A and A share one id: constness says how a type is accessed, not which type it is.
template <typename T>
std::uint32_t type_id() {
    return detail::type_id_of<std::remove_cv_t<T>>();
}

} // namespace ikebana::ecs
