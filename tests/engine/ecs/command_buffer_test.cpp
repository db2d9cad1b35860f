#include <gtest/gtest.h>

#include "engine/ecs/registry.hpp"

using namespace ikebana::ecs;

namespace {
struct Health {
    int value = 0;
};
struct Dead {};
struct Spawned {
    int from = 0;
};
} // namespace

TEST(CommandBuffer, MutationDuringIterationIsDeferredAndApplied) {
    Registry r;
    for (int i = 0; i < 50; ++i) r.emplace<Health>(r.create(), i % 5);
    // Destroy some, tag some, spawn new ones: all while iterating.
    int visited = 0;
    r.view<Health>().each([&](Entity e, Health& h) {
        ++visited;
        if (h.value == 0) {
            r.commands().destroy(e);
        } else if (h.value == 1) {
            r.commands().emplace<Dead>(e);
        } else if (h.value == 2) {
            const Entity child = r.commands().create();
            r.commands().emplace<Spawned>(child, static_cast<int>(e.index));
        } else if (h.value == 3) {
            r.commands().remove<Health>(e);
        }
    });
    EXPECT_EQ(visited, 50) << "deferred changes do not disturb the iteration in progress";
    EXPECT_EQ(r.count<Health>(), 50u) << "nothing applied before the defined point";
    r.commands().apply();
    EXPECT_EQ(r.count<Health>(), 30u); // minus 10 destroyed, 10 with Health removed
    EXPECT_EQ(r.count<Dead>(), 10u);
    EXPECT_EQ(r.count<Spawned>(), 10u);
    EXPECT_EQ(r.commands().pending(), 0u);
}

TEST(CommandBuffer, OperationsOnEntityDestroyedEarlierInBufferAreDropped) {
    Registry r;
    const Entity e = r.create();
    r.commands().destroy(e);
    r.commands().emplace<Health>(e, 3);
    r.commands().apply();
    EXPECT_FALSE(r.valid(e));
    // The slot is recycled by the next create; the dropped emplace must not land on it.
    const Entity recycled = r.create();
    EXPECT_FALSE(r.all_of<Health>(recycled));
}

TEST(CommandBuffer, DeferredFunctionRunsAtApply) {
    Registry r;
    int calls = 0;
    r.commands().defer([&](Registry&) { ++calls; });
    EXPECT_EQ(calls, 0);
    r.commands().apply();
    EXPECT_EQ(calls, 1);
}
