#pragma once
// Component storage: one sparse set per component type. The dense arrays are packed, so iterating one
// component type walks contiguous memory; membership tests are one indexed load into the sparse array.
// docs/ecs.md gives the benchmark that chose this over archetypes for our workload.
#include <cassert>
#include <cstdint>
#include <memory>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/core/hash.hpp"
#include "engine/core/type_name.hpp"
#include "engine/ecs/entity.hpp"

namespace ikebana::ecs {

class SparseSet {
public:
    static constexpr std::uint32_t absent = ~0u;

    virtual ~SparseSet() = default;

protected:
    // Copied only as a whole storage (clone, assign), never sliced.
    SparseSet() = default;
    SparseSet(const SparseSet&) = default;
    SparseSet& operator=(const SparseSet&) = default;

public:

    [[nodiscard]] bool contains(Entity e) const noexcept {
        return e.index < sparse_.size() && sparse_[e.index] != absent && dense_[sparse_[e.index]] == e;
    }
    [[nodiscard]] std::size_t size() const noexcept { return dense_.size(); }
    [[nodiscard]] const std::vector<Entity>& entities() const noexcept { return dense_; }
    [[nodiscard]] std::uint32_t position(Entity e) const noexcept { return sparse_[e.index]; }
    // Room for entities with index below `entity_slots` and for `more` components beyond those held:
    // inserting them later allocates nothing (a structural change on a 1 kHz lane).
    void reserve(std::size_t entity_slots, std::size_t more) {
        sparse_.reserve(entity_slots);
        dense_.reserve(dense_.size() + more);
        reserve_payload(dense_.size() + more);
    }

    // Removes e if present; the type-erased path the registry uses when an entity is destroyed.
    bool erase(Entity e) {
        if (!contains(e)) return false;
        const std::uint32_t pos = sparse_[e.index];
        const Entity last = dense_.back();
        dense_[pos] = last;
        sparse_[last.index] = pos;
        dense_.pop_back();
        sparse_[e.index] = absent;
        swap_and_pop_payload(pos);
        return true;
    }

    // Every entity out.
    void clear() {
        sparse_.clear();
        dense_.clear();
        clear_payload();
    }

    virtual void hash_component(StateHasher& hasher, Entity e) const = 0;
    [[nodiscard]] virtual std::string_view component_name() const noexcept = 0;
    // A copy of this storage, entities and components (a saved registry's); null when the component
    // cannot be copied.
    [[nodiscard]] virtual std::unique_ptr<SparseSet> clone() const = 0;
    // Exchanges contents with `other`, a storage of the same component (restoring a saved registry:
    // the storage object stays where it is, and nothing can fail half-way).
    void swap_contents(SparseSet& other) noexcept {
        sparse_.swap(other.sparse_);
        dense_.swap(other.dense_);
        swap_payload(other);
    }

protected:
    std::uint32_t insert_index(Entity e) {
        if (e.index >= sparse_.size()) sparse_.resize(std::size_t{e.index} + 1, absent);
        assert(sparse_[e.index] == absent);
        sparse_[e.index] = static_cast<std::uint32_t>(dense_.size());
        dense_.push_back(e);
        return sparse_[e.index];
    }
    virtual void swap_and_pop_payload(std::uint32_t pos) = 0;
    virtual void reserve_payload(std::size_t count) = 0;
    virtual void clear_payload() = 0;
    virtual void swap_payload(SparseSet& other) noexcept = 0;

private:
    std::vector<std::uint32_t> sparse_;
    std::vector<Entity> dense_;
};

// Storage of T beside the dense entity array, in the same order.
template <typename T>
class Storage final : public SparseSet {
public:
    template <typename... Args>
    T& emplace(Entity e, Args&&... args) {
        insert_index(e);
        if constexpr (std::is_aggregate_v<T>) {
            return payload_.push_back(T{std::forward<Args>(args)...}), payload_.back();
        } else {
            return payload_.emplace_back(std::forward<Args>(args)...);
        }
    }
    [[nodiscard]] T& get(Entity e) noexcept {
        assert(contains(e));
        return payload_[position(e)];
    }
    [[nodiscard]] const T& get(Entity e) const noexcept {
        assert(contains(e));
        return payload_[position(e)];
    }
    [[nodiscard]] T* try_get(Entity e) noexcept { return contains(e) ? &payload_[position(e)] : nullptr; }
    [[nodiscard]] T* data() noexcept { return payload_.data(); }

    void hash_component(StateHasher& hasher, Entity e) const override { hash_value(hasher, get(e)); }
    [[nodiscard]] std::string_view component_name() const noexcept override { return type_name<T>(); }
    [[nodiscard]] std::unique_ptr<SparseSet> clone() const override {
        if constexpr (std::is_copy_constructible_v<T> && std::is_copy_assignable_v<T>) return std::make_unique<Storage>(*this);
        else return nullptr;
    }

private:
    void swap_and_pop_payload(std::uint32_t pos) override {
        if (pos + 1 != payload_.size()) payload_[pos] = std::move(payload_.back());
        payload_.pop_back();
    }
    void clear_payload() override { payload_.clear(); }
    void reserve_payload(std::size_t count) override { payload_.reserve(count); }
    void swap_payload(SparseSet& other) noexcept override { payload_.swap(static_cast<Storage&>(other).payload_); }

    std::vector<T> payload_;
};

// Tags (empty types) store only membership: every entity shares one instance.
template <typename T>
    requires std::is_empty_v<T>
class Storage<T> final : public SparseSet {
public:
    template <typename... Args>
    T& emplace(Entity e, Args&&...) {
        insert_index(e);
        return instance_;
    }
    [[nodiscard]] T& get([[maybe_unused]] Entity e) noexcept {
        assert(contains(e));
        return instance_;
    }
    [[nodiscard]] T* try_get(Entity e) noexcept { return contains(e) ? &instance_ : nullptr; }

    void hash_component(StateHasher& hasher, Entity) const override { hasher.scalar(std::uint8_t{1}); }
    [[nodiscard]] std::string_view component_name() const noexcept override { return type_name<T>(); }
    [[nodiscard]] std::unique_ptr<SparseSet> clone() const override { return std::make_unique<Storage>(*this); }

private:
    void swap_and_pop_payload(std::uint32_t) override {}
    void clear_payload() override {}
    void reserve_payload(std::size_t) override {}
    void swap_payload(SparseSet&) noexcept override {}
    static inline T instance_{};
};

} // namespace ikebana::ecs
