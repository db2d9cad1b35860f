#pragma once
// How a system introduces itself to the scheduler: its name, which rate it runs at, which lane (thread)
// and phase it belongs to, and the components it reads and writes. The declared access is what the
// scheduler checks for conflicting writers before anything runs.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/type_name.hpp"
#include "engine/ecs/fwd.hpp"

namespace ikebana::sched {

// What a system sees when it runs. dt_s is the exact span from this firing to the next on the
// integer-microsecond timeline (a 30 Hz system alternates 33333 and 33334 µs), never frame delta.
struct SystemContext {
    ecs::Registry& registry;
    std::int64_t time_us;
    double dt_s;
    std::uint64_t firing; // how many times this system has fired before
};

using SystemFn = std::function<void(SystemContext&)>;

struct SystemDesc {
    std::string name;
    std::string lane = "main";   // which world and thread ("haptic" runs on its own thread in real time)
    std::string phase;           // the lane's phases run in their declared order at equal timestamps
    std::string rate;            // a rate name from the RateTable ("haptic", "render", ...)
    std::vector<std::string> reads;
    std::vector<std::string> writes;
    std::vector<std::string> after; // systems of the same phase this one must follow
    SystemFn run;
};

template <typename... T>
std::vector<std::string> components() {
    return {std::string(type_name<T>())...};
}

// A system written as a class declares itself with static members; see systems/ for examples.
template <typename S>
concept DescribedSystem = requires(S s, SystemContext& ctx) {
    { S::name } -> std::convertible_to<std::string_view>;
    { S::lane } -> std::convertible_to<std::string_view>;
    { S::phase } -> std::convertible_to<std::string_view>;
    { S::rate } -> std::convertible_to<std::string_view>;
    typename S::reads;
    typename S::writes;
    s(ctx);
};

template <typename... T>
struct Components {
    static std::vector<std::string> names() { return components<T...>(); }
};

template <DescribedSystem S>
SystemDesc describe(S system = {}, std::vector<std::string> after = {}) {
    SystemDesc d;
    d.name = std::string(S::name);
    d.lane = std::string(S::lane);
    d.phase = std::string(S::phase);
    d.rate = std::string(S::rate);
    d.reads = S::reads::names();
    d.writes = S::writes::names();
    d.after = std::move(after);
    d.run = [system](SystemContext& ctx) mutable { system(ctx); };
    return d;
}

} // namespace ikebana::sched
