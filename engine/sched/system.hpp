#pragma once
// How a system introduces itself to the scheduler: its name, which rate it runs at, which lane (thread)
// and phase it belongs to, and the components and resources it reads and writes. The declared access
// is what the scheduler checks for conflicting writers before anything runs, and, for systems
// described from a class (describe<S>), what the registry holds every access to while the system runs:
// an undeclared read or write throws ecs::UndeclaredAccess naming the system and the type, so the first
// test that reaches it fails (engine/ecs/registry.hpp).
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/type_name.hpp"
#include "engine/ecs/fwd.hpp"
#include "engine/ecs/type_id.hpp"

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
    std::string module;             // set by the schedule: the module that installed it, if any
    // Type ids of the declared access, for the run-time check; `checked` is false for descriptions
    // written by hand with names only (tests of the scheduler itself).
    bool checked = false;
    std::vector<std::uint32_t> read_ids;
    std::vector<std::uint32_t> write_ids;
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

// Components and resources alike: a resource is declared by its type, e.g. Components<render::DrawList>.
template <typename... T>
struct Components {
    static std::vector<std::string> names() { return components<T...>(); }
    static std::vector<std::uint32_t> ids() { return {ecs::type_id<T>()...}; }
};

// One list from several: what a shared helper reads, plus what the system itself reads.
template <typename... Lists>
struct Join;
template <typename... A>
struct Join<Components<A...>> {
    using type = Components<A...>;
};
template <typename... A, typename... B, typename... Rest>
struct Join<Components<A...>, Components<B...>, Rest...> : Join<Components<A..., B...>, Rest...> {};
template <typename... Lists>
using Joined = typename Join<Lists...>::type;

template <DescribedSystem S>
SystemDesc describe(S system = {}, std::vector<std::string> after = {}) {
    SystemDesc d;
    d.name = std::string(S::name);
    d.lane = std::string(S::lane);
    d.phase = std::string(S::phase);
    d.rate = std::string(S::rate);
    d.reads = S::reads::names();
    d.writes = S::writes::names();
    d.checked = true;
    d.read_ids = S::reads::ids();
    d.write_ids = S::writes::ids();
    d.after = std::move(after);
    d.run = [system](SystemContext& ctx) mutable { system(ctx); };
    return d;
}

} // namespace ikebana::sched
