#include "engine/ecs/hierarchy.hpp"

#include <algorithm>
#include <stdexcept>

#include "engine/ecs/registry.hpp"

namespace ikebana::ecs {

void attach(Registry& registry, Entity child, Entity parent) {
    if (!registry.valid(child) || !registry.valid(parent)) throw std::logic_error("attach: invalid entity handle");
    if (child == parent) throw std::logic_error("attach: an entity cannot own itself");
    for (Entity up = parent; !up.is_null(); up = parent_of(registry, up)) {
        if (up == child) throw std::logic_error("attach: would make an ownership cycle");
    }
    detach(registry, child);
    registry.emplace<ChildOf>(child, parent);
    if (auto* children = registry.try_get<Children>(parent)) {
        children->entities.push_back(child);
    } else {
        registry.emplace<Children>(parent, std::vector<Entity>{child});
    }
}

void detach(Registry& registry, Entity child) {
    auto* link = registry.try_get<ChildOf>(child);
    if (!link) return;
    if (auto* siblings = registry.try_get<Children>(link->parent)) std::erase(siblings->entities, child);
    registry.remove<ChildOf>(child);
}

Entity parent_of(Registry& registry, Entity child) {
    const auto* link = registry.try_get<ChildOf>(child);
    return link ? link->parent : null_entity;
}

const std::vector<Entity>& children_of(Registry& registry, Entity parent) {
    static const std::vector<Entity> none;
    const auto* children = registry.try_get<Children>(parent);
    return children ? children->entities : none;
}

} // namespace ikebana::ecs
