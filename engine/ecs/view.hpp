#pragma once
// Views over entities that have every Get component and none of the Excluded ones. Iteration walks the
// smallest of the Get storages and tests membership in the others. Tags (empty types) filter but are
// not passed to the callback. A const Get (`view<const HandState, Grasp>`) is passed as a const
// reference and counts as a read; the others as writes (checked against the running system's
// declaration, registry.hpp).
#include <algorithm>
#include <tuple>
#include <type_traits>

#include "engine/ecs/registry.hpp"

namespace ikebana::ecs {

template <typename... Get, typename... Excluded>
class View<std::tuple<Get...>, std::tuple<Excluded...>> {
    static_assert(sizeof...(Get) > 0, "a view needs at least one component");

public:
    explicit View(Registry& registry) : registry_(registry) {
        (registry_.template check_access<Get>(), ...);
        (registry_.template check_access<const Excluded>(), ...);
    }

    // f(entity, components...) with the non-empty Get components by reference.
    template <typename F>
    void each(F&& f) {
        for_matching([&](Entity e, const auto& pools) {
            std::apply([&](auto&... components) { f(e, components...); },
                       std::tuple_cat(fetch<Get>(std::get<Pool<Get>*>(pools), e)...));
        });
    }

    // Number of entities that match (walks the smallest storage).
    [[nodiscard]] std::size_t size() {
        std::size_t n = 0;
        each_entity([&n](Entity) { ++n; });
        return n;
    }

    template <typename F>
    void each_entity(F&& f) {
        for_matching([&](Entity e, const auto&) { f(e); });
    }

private:
    struct IterationScope {
        explicit IterationScope(Registry& r) : r_(r) { ++r_.iteration_depth_; }
        ~IterationScope() { --r_.iteration_depth_; }
        Registry& r_;
    };

    // Calls visit(entity, pools) for every entity with all Get and no Excluded components. Storages are
    // resolved once per call; structural changes are refused meanwhile, so the dense array cannot move.
    template <typename Visit>
    void for_matching(Visit&& visit) {
        const SparseSet* lead = smallest();
        if (!lead) return;
        IterationScope scope(registry_);
        const std::tuple<Pool<Get>*...> pools{registry_.template find_storage<std::remove_const_t<Get>>()...};
        const std::tuple<Storage<Excluded>*...> excluded{registry_.template find_storage<Excluded>()...};
        for (const Entity e : lead->entities()) {
            if (!(std::get<Pool<Get>*>(pools)->contains(e) && ...)) continue;
            if (((std::get<Storage<Excluded>*>(excluded) && std::get<Storage<Excluded>*>(excluded)->contains(e)) || ...)) continue;
            visit(e, pools);
        }
    }

    template <typename T>
    using Pool = Storage<std::remove_const_t<T>>;

    template <typename T>
    static auto fetch(Pool<T>* pool, Entity e) {
        if constexpr (std::is_empty_v<std::remove_const_t<T>>) return std::tuple<>{};
        else return std::tuple<T&>{pool->get(e)};
    }

    const SparseSet* smallest() const {
        const SparseSet* pools[] = {registry_.template find_storage<std::remove_const_t<Get>>()...};
        const SparseSet* best = nullptr;
        for (const SparseSet* p : pools) {
            if (!p) return nullptr; // a component nobody has: the view is empty
            if (!best || p->size() < best->size()) best = p;
        }
        return best;
    }

    Registry& registry_;
};

template <typename... Get, typename... Excluded>
View<std::tuple<Get...>, std::tuple<Excluded...>> Registry::view(Exclude<Excluded...>) {
    return View<std::tuple<Get...>, std::tuple<Excluded...>>(*this);
}

inline Entity CommandBuffer::create() { return registry_.create(); }

inline void CommandBuffer::destroy(Entity e) {
    ops_.emplace_back([e](Registry& r) { r.destroy(e); });
}

template <typename T, typename... Args>
void CommandBuffer::emplace(Entity e, Args&&... args) {
    // Checked as it is queued, against the system queuing it: a deferred write is still that system's.
    registry_.template check_access<T>();
    ops_.emplace_back([e, value = make<T>(std::forward<Args>(args)...)](Registry& r) mutable {
        if (r.valid(e)) r.template emplace_or_replace<T>(e, std::move(value));
    });
}

template <typename T>
void CommandBuffer::remove(Entity e) {
    registry_.template check_access<T>();
    ops_.emplace_back([e](Registry& r) { r.template remove<T>(e); });
}

inline void CommandBuffer::apply() {
    // Index loop: an applied operation may queue more.
    for (std::size_t i = 0; i < ops_.size(); ++i) {
        auto op = std::move(ops_[i]);
        op(registry_);
    }
    ops_.clear();
}

} // namespace ikebana::ecs
