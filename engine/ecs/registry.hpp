#pragma once
// The registry owns entities and their components. Structural changes (create, destroy, emplace,
// remove) are refused while a view is being iterated: systems queue them in the registry's command
// buffer, and the scheduler applies that buffer after each system, at a defined point.
#include <algorithm>
#include <any>
#include <atomic>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <typeindex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/core/hash.hpp"
#include "engine/core/result.hpp"
#include "engine/core/type_name.hpp"
#include "engine/ecs/command_buffer.hpp"
#include "engine/ecs/entity.hpp"
#include "engine/ecs/hierarchy.hpp"
#include "engine/ecs/sparse_set.hpp"
#include "engine/ecs/type_id.hpp"

namespace ikebana::ecs {

namespace detail {
template <typename T>
std::uint32_t component_id() {
    return type_id<T>();
}
} // namespace detail

// What the system running now declared it reads and writes, by type id: none, read, or write (which
// includes reading). Set by the scheduler around each firing; nullptr outside systems (set-up, tests,
// the command buffer), where nothing is checked.
struct AccessMask {
    enum : std::uint8_t { none = 0, read = 1, write = 2 };
    std::string system;
    std::vector<std::uint8_t> by_type;
    // What the system has really done so far (none, read, write), by type id: a declaration wider than
    // this, after a run that exercised the system, is reported (Schedule::unused_access). Written only
    // by the thread running the system, read after its clock stopped; as long as by_type.
    mutable std::vector<std::uint8_t> used;
};

// An access the running system did not declare: a programming error, found by the first test or run
// that reaches it, never a silent race.
class UndeclaredAccess : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

// How a resource takes back a saved value (Registry::restore), from a fresh copy of it: by default
// the whole value. A resource that wires a lane to something outside the registry (a Port, the
// devices a session opened) overloads this, found by argument-dependent lookup, to keep its wiring
// and take only its state (or nothing).
template <typename T>
void restore_resource(T& into, T&& saved) noexcept {
    into = std::move(saved);
}

class Registry;

// A registry's whole state kept aside: its entities, every component and every resource (a replay's
// snapshots, to go back to a moment without playing the recording again from its start). Made by
// Registry::save, put back by Registry::restore, as often as wanted.
class SavedRegistry {
public:
    SavedRegistry() = default;
    SavedRegistry(SavedRegistry&&) noexcept = default;
    SavedRegistry& operator=(SavedRegistry&&) noexcept = default;
    [[nodiscard]] std::size_t entity_slots() const noexcept { return slots_.size(); }

private:
    friend class Registry;
    struct Slot {
        std::uint32_t generation;
        bool alive;
    };
    struct Resource {
        std::type_index type{typeid(void)};
        std::shared_ptr<void> value;
        std::string_view name;
        std::shared_ptr<void> (*copy)(const void*) = nullptr;
        void (*restore)(void* into, void* fresh) = nullptr;
    };
    std::vector<Slot> slots_;
    std::vector<std::uint32_t> free_;
    std::vector<std::unique_ptr<SparseSet>> pools_; // by component id, as the registry's
    std::vector<Resource> resources_;
};

template <typename... T>
struct Exclude {};
template <typename... T>
inline constexpr Exclude<T...> exclude{};

template <typename Get, typename Excluded>
class View;

class Registry {
    struct ResourceSlot {
        std::shared_ptr<void> value;
        std::string_view name;
        std::shared_ptr<void> (*copy)(const void*) = nullptr; // null: not copyable (save refuses)
        void (*restore)(void* into, void* fresh) = nullptr;
    };
    using Slot = SavedRegistry::Slot;

public:
    // A restore made ready (stage_restore: every copy it needs, taken aside) and not yet put in
    // (commit_restore, which cannot fail): several registries are restored all or none.
    class StagedRestore {
    public:
        StagedRestore(StagedRestore&&) noexcept = default;

    private:
        friend class Registry;
        StagedRestore() = default;
        const SavedRegistry* from = nullptr;
        std::vector<Slot> slots;
        std::vector<std::uint32_t> free;
        std::vector<std::unique_ptr<SparseSet>> pools;
        std::vector<std::shared_ptr<void>> values; // fresh copies of the saved resources, in their order
        std::vector<std::type_index> extra;        // resources made after the save: they go
        std::unordered_map<std::type_index, ResourceSlot> missing; // saved ones this registry lacks, ready to go in
    };

    Registry() : commands_(*this) {}
    Registry(const Registry&) = delete;
    Registry& operator=(const Registry&) = delete;

    // --- entities -----------------------------------------------------------------------------------
    // Creating an entity touches no component storage, so it is allowed during iteration.
    Entity create() {
        if (!free_.empty()) {
            const std::uint32_t index = free_.back();
            free_.pop_back();
            slots_[index].alive = true;
            return Entity{index, slots_[index].generation};
        }
        slots_.push_back(Slot{0, true});
        // Every slot can be freed without the list of free ones growing (destroy allocates nothing).
        if (free_.capacity() < slots_.capacity()) free_.reserve(slots_.capacity());
        return Entity{static_cast<std::uint32_t>(slots_.size() - 1), 0};
    }

    // Room for `more` entities beyond those alive, in the entity list and in every storage's index, so
    // that creating them allocates nothing; reserve<T> adds room for their components. What a 1 kHz lane
    // builds at run time (a stripped leaf's stalk) draws on this, reserved when its scene loads.
    void reserve_entities(std::size_t more) {
        const std::size_t slots = alive() + more;
        if (slots > slots_.size()) slots_.reserve(slots);
        free_.reserve(slots_.capacity());
        for (auto& pool : pools_) {
            if (pool) pool->reserve(slots_.capacity(), 0);
        }
    }
    template <typename T>
    void reserve(std::size_t more) {
        storage<T>().reserve(std::max(slots_.capacity(), slots_.size()), more);
    }

    [[nodiscard]] bool valid(Entity e) const noexcept {
        return e.index < slots_.size() && slots_[e.index].alive && slots_[e.index].generation == e.generation;
    }

    // Destroys e, every component it has and, through the hierarchy, every entity it owns.
    void destroy(Entity e) {
        guard_structural("destroy");
        if (!valid(e)) return;
        // Each child in turn, first to last: destroying one takes it off the list (no copy of the list, so
        // a destroy on a 1 kHz lane allocates nothing). One that is no longer valid is taken off by hand.
        for (auto* children = try_get<Children>(e); children && !children->entities.empty(); children = try_get<Children>(e)) {
            const Entity child = children->entities.front();
            const auto* link = try_get<ChildOf>(child);
            if (link && link->parent == e) destroy(child); // takes it off the list
            else children->entities.erase(children->entities.begin());
        }
        if (auto* link = try_get<ChildOf>(e); link && valid(link->parent)) {
            if (auto* siblings = try_get<Children>(link->parent)) {
                std::erase(siblings->entities, e);
            }
        }
        for (auto& pool : pools_) {
            if (pool) pool->erase(e);
        }
        Slot& slot = slots_[e.index];
        slot.alive = false;
        ++slot.generation; // every outstanding handle to e is now invalid
        free_.push_back(e.index);
    }

    [[nodiscard]] std::size_t alive() const noexcept { return slots_.size() - free_.size(); }

    // --- components ---------------------------------------------------------------------------------
    template <typename T, typename... Args>
    T& emplace(Entity e, Args&&... args) {
        guard_structural("emplace");
        require_valid(e, "emplace");
        auto& pool = storage<T>();
        if (pool.contains(e)) throw std::logic_error("emplace: entity already has " + std::string(type_name<T>()));
        return pool.emplace(e, std::forward<Args>(args)...);
    }

    template <typename T, typename... Args>
    T& emplace_or_replace(Entity e, Args&&... args) {
        if (auto* existing = try_get<T>(e)) {
            if constexpr (std::is_aggregate_v<T>) *existing = T{std::forward<Args>(args)...};
            else *existing = T(std::forward<Args>(args)...);
            return *existing;
        }
        return emplace<T>(e, std::forward<Args>(args)...);
    }

    template <typename T>
    bool remove(Entity e) {
        guard_structural("remove");
        if (!valid(e)) return false;
        return storage<T>().erase(e);
    }

    // get<const T> and try_get<const T> read; get<T> and try_get<T> may write (and are checked so).
    template <typename T>
    [[nodiscard]] T& get(Entity e) {
        check_access<T>();
        require_valid(e, "get");
        auto* component = storage<std::remove_const_t<T>>().try_get(e);
        if (!component) throw std::logic_error("get: entity has no " + std::string(type_name<std::remove_const_t<T>>()));
        return *component;
    }

    template <typename T>
    [[nodiscard]] T* try_get(Entity e) {
        check_access<T>();
        if (!valid(e)) return nullptr;
        auto* pool = find_storage<std::remove_const_t<T>>();
        return pool ? pool->try_get(e) : nullptr;
    }

    template <typename... T>
    [[nodiscard]] bool all_of(Entity e) const {
        (check_access<const T>(), ...);
        return valid(e) && (has_one<T>(e) && ...);
    }

    template <typename... T>
    [[nodiscard]] bool any_of(Entity e) const {
        (check_access<const T>(), ...);
        return valid(e) && (has_one<T>(e) || ...);
    }

    // The component of the one entity that has T (the kenzan, the world's random stream), or null.
    // With several, the first in storage order.
    template <typename T>
    [[nodiscard]] T* single() {
        check_access<T>();
        auto* pool = find_storage<std::remove_const_t<T>>();
        return pool && pool->size() > 0 ? pool->try_get(pool->entities().front()) : nullptr;
    }

    template <typename T>
    [[nodiscard]] std::size_t count() const {
        check_access<const T>();
        const auto* pool = find_storage<T>();
        return pool ? pool->size() : 0;
    }

    // --- declared access ------------------------------------------------------------------------------
    // While `mask` is set, every component and resource access is checked against it: a const T needs
    // T declared read or written, a mutable T needs it declared written. The scheduler sets it around
    // each system it runs.
    void set_access_mask(const AccessMask* mask) noexcept { access_ = mask; }
    [[nodiscard]] const AccessMask* access_mask() const noexcept { return access_; }

    // --- iteration ----------------------------------------------------------------------------------
    template <typename... Get, typename... Excluded>
    [[nodiscard]] View<std::tuple<Get...>, std::tuple<Excluded...>> view(Exclude<Excluded...> = {});

    // The deferred structural changes of the system that is running now.
    [[nodiscard]] CommandBuffer& commands() noexcept { return commands_; }
    [[nodiscard]] bool iterating() const noexcept { return iteration_depth_ > 0; }

    // --- singletons (EnTT's context): per-world resources such as configuration and RNG state ------
    // No pointer is a resource: `resource<T* const>()` passed the read check while the system wrote
    // through it. What lives outside the registry is held in an ecs::Port (engine/ecs/port.hpp).
    template <typename T, typename... Args>
        requires(!std::is_pointer_v<T>)
    T& set_resource(Args&&... args) {
        check_access<T>();
        auto& slot = resources_[std::type_index(typeid(T))];
        if constexpr (std::is_aggregate_v<T>) slot.value = std::make_shared<T>(T{std::forward<Args>(args)...});
        else slot.value = std::make_shared<T>(std::forward<Args>(args)...);
        slot.name = type_name<T>();
        if constexpr (std::is_copy_constructible_v<T>) {
            slot.copy = [](const void* from) -> std::shared_ptr<void> { return std::make_shared<T>(*static_cast<const T*>(from)); };
            slot.restore = [](void* into, void* fresh) { restore_resource(*static_cast<T*>(into), std::move(*static_cast<T*>(fresh))); };
        } else {
            slot.copy = nullptr;
            slot.restore = nullptr;
        }
        return *std::static_pointer_cast<T>(slot.value);
    }
    // resource<const T>() reads, resource<T>() may write (and is checked so).
    template <typename T>
        requires(!std::is_pointer_v<std::remove_const_t<T>>)
    [[nodiscard]] T* resource() {
        check_access<T>();
        auto it = resources_.find(std::type_index(typeid(T)));
        return it == resources_.end() ? nullptr : static_cast<T*>(it->second.value.get());
    }

    // --- saved state --------------------------------------------------------------------------------
    // Outside any system. A component or resource that cannot be copied is named in the error (and
    // nothing is saved).
    [[nodiscard]] Result<SavedRegistry> save() const {
        if (iteration_depth_ > 0) return make_error(ErrorCode::invalid_argument, "save: during view iteration");
        SavedRegistry saved;
        saved.slots_ = slots_;
        saved.free_ = free_;
        saved.pools_.resize(pools_.size());
        for (std::size_t id = 0; id < pools_.size(); ++id) {
            if (!pools_[id]) continue;
            saved.pools_[id] = pools_[id]->clone();
            if (!saved.pools_[id]) return make_error(ErrorCode::invalid_argument, "save: component '" + std::string(pools_[id]->component_name()) + "' cannot be copied");
        }
        for (const auto& [type, slot] : resources_) {
            if (!slot.copy) return make_error(ErrorCode::invalid_argument, "save: resource '" + std::string(slot.name) + "' cannot be copied");
            saved.resources_.push_back({type, slot.copy(slot.value.get()), slot.name, slot.copy, slot.restore});
        }
        return saved;
    }
    // Back to `saved`, a save of this registry or of one built the same way (another world of the same
    // scene): entities and components as they were; each saved resource given back its value through
    // restore_resource (a Port keeps its target); a resource made since the save (a system's scratch,
    // made at its first firing) goes, so that the registry is the saved one's to the byte. Storages and
    // kept resources stay where they are: what holds a reference to one still does. All or nothing:
    // an allocation that fails leaves the registry as it was.
    void restore(const SavedRegistry& saved) { commit_restore(stage_restore(saved)); }
    // The two halves of restore: every copy made aside (may throw; changes nothing but the room kept
    // for resources), then put in (cannot fail).
    [[nodiscard]] StagedRestore stage_restore(const SavedRegistry& saved) {
        guard_structural("restore");
        StagedRestore staged;
        staged.from = &saved;
        staged.slots = saved.slots_;
        staged.free = saved.free_;
        staged.pools.resize(saved.pools_.size());
        for (std::size_t id = 0; id < saved.pools_.size(); ++id) {
            if (saved.pools_[id]) staged.pools[id] = saved.pools_[id]->clone();
        }
        for (const auto& r : saved.resources_) {
            staged.values.push_back(r.copy(r.value.get()));
            if (!resources_.count(r.type)) staged.missing.emplace(r.type, ResourceSlot{staged.values.back(), r.name, r.copy, r.restore});
        }
        for (const auto& entry : resources_) { // (not a structured binding: clang 14 cannot capture one in a lambda)
            const std::type_index type = entry.first;
            if (std::none_of(saved.resources_.begin(), saved.resources_.end(), [&](const auto& r) { return r.type == type; })) staged.extra.push_back(type);
        }
        if (pools_.size() < staged.pools.size()) pools_.resize(staged.pools.size());
        resources_.reserve(resources_.size() + staged.missing.size()); // the commit then never rehashes
        return staged;
    }
    void commit_restore(StagedRestore&& staged) noexcept {
        const SavedRegistry& saved = *staged.from;
        slots_.swap(staged.slots);
        free_.swap(staged.free);
        for (std::size_t id = 0; id < pools_.size(); ++id) {
            SparseSet* from = id < staged.pools.size() ? staged.pools[id].get() : nullptr;
            if (from && pools_[id]) pools_[id]->swap_contents(*from);
            else if (from) pools_[id] = std::move(staged.pools[id]);
            else if (pools_[id]) pools_[id]->clear();
        }
        for (const auto& type : staged.extra) resources_.erase(type);
        for (std::size_t i = 0; i < saved.resources_.size(); ++i) {
            auto it = resources_.find(saved.resources_[i].type);
            if (it != resources_.end()) it->second.restore(it->second.value.get(), staged.values[i].get());
        }
        // Made by a system after this registry's start: the copy is it (nodes made in stage_restore).
        while (!staged.missing.empty()) resources_.insert(staged.missing.extract(staged.missing.begin()));
    }

    // --- state hash ---------------------------------------------------------------------------------
    // Independent of the order in which types were first used and of the order of the dense arrays:
    // storages are visited by component name and entities by handle.
    // Each component type's share of the state hash, by name: where two runs that should agree part.
    [[nodiscard]] std::vector<std::pair<std::string, std::uint64_t>> component_hashes() const {
        std::vector<std::pair<std::string, std::uint64_t>> out;
        for (const auto& pool : pools_) {
            if (!pool || pool->size() == 0) continue;
            StateHasher hasher;
            auto entities = pool->entities();
            std::sort(entities.begin(), entities.end());
            for (const Entity e : entities) {
                hasher.scalar(e.bits());
                pool->hash_component(hasher, e);
            }
            out.emplace_back(std::string(pool->component_name()), hasher.digest());
        }
        std::sort(out.begin(), out.end());
        return out;
    }

    [[nodiscard]] std::uint64_t state_hash() const {
        std::vector<const SparseSet*> pools;
        for (const auto& pool : pools_) {
            if (pool && pool->size() > 0) pools.push_back(pool.get());
        }
        std::sort(pools.begin(), pools.end(), [](const SparseSet* a, const SparseSet* b) {
            return a->component_name() < b->component_name();
        });
        StateHasher hasher;
        hasher.scalar(static_cast<std::uint64_t>(alive()));
        std::vector<Entity> entities;
        for (const SparseSet* pool : pools) {
            hash_value(hasher, pool->component_name());
            entities = pool->entities();
            std::sort(entities.begin(), entities.end());
            for (const Entity e : entities) {
                hasher.scalar(e.bits());
                pool->hash_component(hasher, e);
            }
        }
        return hasher.digest();
    }

    template <typename T>
    [[nodiscard]] Storage<T>& storage() {
        const auto id = detail::component_id<T>();
        if (id >= pools_.size()) pools_.resize(std::size_t{id} + 1);
        if (!pools_[id]) pools_[id] = std::make_unique<Storage<T>>();
        return static_cast<Storage<T>&>(*pools_[id]);
    }

private:
    template <typename, typename>
    friend class View;
    friend class CommandBuffer; // checks a queued emplace or remove against the system queuing it

    template <typename T>
    [[nodiscard]] Storage<T>* find_storage() const noexcept {
        const auto id = detail::component_id<T>();
        return id < pools_.size() ? static_cast<Storage<T>*>(pools_[id].get()) : nullptr;
    }
    template <typename T>
    [[nodiscard]] bool has_one(Entity e) const {
        const auto* pool = find_storage<T>();
        return pool && pool->contains(e);
    }
    template <typename T>
    void check_access() const {
        if (!access_) [[likely]] return;
        const auto id = type_id<T>();
        const std::uint8_t declared = id < access_->by_type.size() ? access_->by_type[id] : std::uint8_t{AccessMask::none};
        const bool writes = !std::is_const_v<T>;
        if (declared == AccessMask::write || (declared == AccessMask::read && !writes)) {
            const std::uint8_t level = writes ? AccessMask::write : AccessMask::read;
            // Sized with by_type when the mask was made (a declared id is inside it): nothing allocates here.
            if (access_->used[id] < level) access_->used[id] = level;
            return;
        }
        throw UndeclaredAccess("system '" + access_->system + "' " + (writes ? "writes" : "reads") + " '" +
                               std::string(type_name<std::remove_const_t<T>>()) + "' without declaring it" +
                               (declared == AccessMask::read ? " (declared read only: view it as const)" : ""));
    }
    void guard_structural(const char* what) const {
        if (iteration_depth_ > 0) {
            throw std::logic_error(std::string(what) +
                                   " during view iteration: queue it with registry.commands() instead");
        }
    }
    void require_valid(Entity e, const char* what) const {
        if (!valid(e)) throw std::logic_error(std::string(what) + ": invalid (destroyed or null) entity handle");
    }

    std::vector<Slot> slots_;
    std::vector<std::uint32_t> free_;
    std::vector<std::unique_ptr<SparseSet>> pools_;
    std::unordered_map<std::type_index, ResourceSlot> resources_;
    CommandBuffer commands_;
    int iteration_depth_ = 0;
    const AccessMask* access_ = nullptr;
};

} // namespace ikebana::ecs

#include "engine/ecs/view.hpp"
