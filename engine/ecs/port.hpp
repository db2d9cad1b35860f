#pragma once
// A lane's end of something that lives outside its registry and is shared with another lane or
// thread: a channel the world owns, the devices a session opened. A registry refuses raw pointers as
// resources (registry.hpp), because `resource<T* const>()` passed the read check while the system wrote
// through the pointer. A Port hands its target out only from a non-const Port, so using it at all is
// a write of the Port's type: declared as one, checked as one, and ordered against every other user.
namespace ikebana::ecs {

template <typename T>
class Port {
public:
    explicit Port(T& target) noexcept : target_(&target) {}
    // Using the target (sending on a channel, taking from it, talking to a device): a write.
    [[nodiscard]] T& use() noexcept { return *target_; }

private:
    T* target_;
};

// A restored registry keeps its own ports (registry.hpp's restore_resource): a saved one may come
// from another world, and its target is that world's.
template <typename T>
void restore_resource(Port<T>&, Port<T>&&) noexcept {}

} // namespace ikebana::ecs
