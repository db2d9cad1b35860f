#pragma once
// Deferred structural changes. A system iterating a view queues its creates, destroys, emplaces and
// removes here; the scheduler applies them after the system returns, in the order they were queued.
// Operations on an entity that an earlier queued operation destroyed are dropped, not applied to a
// recycled slot (the generation check sees to that).
#include <functional>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/ecs/entity.hpp"
#include "engine/ecs/fwd.hpp"

namespace ikebana::ecs {

class CommandBuffer {
public:
    // Room for 64 queued operations from the start: a system on a 1 kHz lane that queues a few (a cut's
    // request removed) allocates nothing. An operation whose captures pass std::function's small buffer
    // (two pointers) still allocates: queue a pointer to the system's own data instead.
    explicit CommandBuffer(Registry& registry) : registry_(registry) { ops_.reserve(64); }

    // The handle is valid at once (creating touches no storage); its components arrive on apply().
    Entity create();

    // Defined after Registry (engine/ecs/view.hpp): the queued operations call into it, and a
    // compiler may check them as soon as they are wrapped (clang does).
    void destroy(Entity e);
    template <typename T, typename... Args>
    void emplace(Entity e, Args&&... args);
    template <typename T>
    void remove(Entity e);

    // Any other change that must wait until iteration ends.
    void defer(std::function<void(Registry&)> op) { ops_.push_back(std::move(op)); }

    [[nodiscard]] std::size_t pending() const noexcept { return ops_.size(); }

    // Applies everything queued so far. Operations queued while applying run in the same call.
    void apply();

private:
    template <typename T, typename... Args>
    static T make(Args&&... args) {
        if constexpr (std::is_aggregate_v<T>) return T{std::forward<Args>(args)...};
        else return T(std::forward<Args>(args)...);
    }

    Registry& registry_;
    std::vector<std::function<void(Registry&)>> ops_;
};

} // namespace ikebana::ecs
