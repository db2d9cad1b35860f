#pragma once
// Ownership between entities (a flower owns its parts). Destroying a parent destroys what it owns;
// the registry keeps both directions consistent.
#include <vector>

#include "engine/ecs/entity.hpp"
#include "engine/ecs/fwd.hpp"

namespace ikebana::ecs {

struct ChildOf {
    Entity parent;
};

struct Children {
    std::vector<Entity> entities; // in the order they were attached
};

// Makes child owned by parent (detaching it from a previous parent first).
void attach(Registry& registry, Entity child, Entity parent);
// Ends the ownership; child lives on as a root.
void detach(Registry& registry, Entity child);
[[nodiscard]] Entity parent_of(Registry& registry, Entity child);
[[nodiscard]] const std::vector<Entity>& children_of(Registry& registry, Entity parent);

} // namespace ikebana::ecs
