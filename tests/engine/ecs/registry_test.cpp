#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include "engine/ecs/port.hpp"
#include "engine/ecs/registry.hpp"

using namespace ikebana::ecs;

namespace {
struct Position {
    glm::dvec3 value{};
};
struct Velocity {
    glm::dvec3 value{};
};
struct Frozen {}; // a tag
} // namespace

TEST(Registry, CreatedEntityIsValid) {
    Registry r;
    const Entity e = r.create();
    EXPECT_TRUE(r.valid(e));
    EXPECT_EQ(r.alive(), 1u);
}

TEST(Registry, DestroyedHandleIsNotValid) {
    Registry r;
    const Entity e = r.create();
    r.destroy(e);
    EXPECT_FALSE(r.valid(e));
    EXPECT_EQ(r.alive(), 0u);
}

TEST(Registry, RecycledSlotDoesNotAliasOldHandle) {
    Registry r;
    const Entity old = r.create();
    r.emplace<Position>(old, glm::dvec3{1, 2, 3});
    r.destroy(old);
    const Entity recycled = r.create();
    ASSERT_EQ(recycled.index, old.index) << "the slot is reused";
    EXPECT_NE(recycled.generation, old.generation);
    EXPECT_FALSE(r.valid(old));
    EXPECT_TRUE(r.valid(recycled));
    EXPECT_EQ(r.try_get<Position>(old), nullptr) << "a stale handle must not reach the new entity's data";
    EXPECT_FALSE(r.all_of<Position>(recycled)) << "components of the destroyed entity are gone";
}

TEST(Registry, NullHandleIsNotValid) {
    Registry r;
    EXPECT_FALSE(r.valid(null_entity));
    EXPECT_THROW((void)r.get<Position>(null_entity), std::logic_error);
}

TEST(Registry, EmplaceGetRemove) {
    Registry r;
    const Entity e = r.create();
    r.emplace<Position>(e, glm::dvec3{1, 2, 3});
    EXPECT_TRUE(r.all_of<Position>(e));
    EXPECT_EQ(r.get<Position>(e).value.y, 2.0);
    EXPECT_TRUE(r.remove<Position>(e));
    EXPECT_FALSE(r.all_of<Position>(e));
    EXPECT_FALSE(r.remove<Position>(e));
}

TEST(Registry, EmplaceTwiceIsRefused) {
    Registry r;
    const Entity e = r.create();
    r.emplace<Position>(e);
    EXPECT_THROW(r.emplace<Position>(e), std::logic_error);
}

TEST(Registry, RemovingFromMiddleKeepsOthersIntact) {
    Registry r;
    std::vector<Entity> es;
    for (int i = 0; i < 10; ++i) {
        es.push_back(r.create());
        r.emplace<Position>(es.back(), glm::dvec3{i, 0, 0});
    }
    r.destroy(es[3]);
    r.remove<Position>(es[7]);
    for (int i = 0; i < 10; ++i) {
        if (i == 3 || i == 7) continue;
        EXPECT_EQ(r.get<Position>(es[i]).value.x, i);
    }
    EXPECT_EQ(r.count<Position>(), 8u);
}

TEST(Registry, TagsTakeNoPayloadButFilter) {
    Registry r;
    const Entity a = r.create();
    const Entity b = r.create();
    r.emplace<Frozen>(a);
    EXPECT_TRUE(r.all_of<Frozen>(a));
    EXPECT_FALSE(r.all_of<Frozen>(b));
    EXPECT_TRUE((r.any_of<Position, Frozen>(a)));
}

TEST(Registry, ResourcesAreSingletons) {
    Registry r;
    EXPECT_EQ(r.resource<int>(), nullptr);
    r.set_resource<int>(7);
    ASSERT_NE(r.resource<int>(), nullptr);
    EXPECT_EQ(*r.resource<int>(), 7);
}

TEST(Registry, StateHashIgnoresInsertionOrderOfTypes) {
    Registry a;
    Registry b;
    const Entity ea = a.create();
    const Entity eb = b.create();
    a.emplace<Position>(ea, glm::dvec3{1, 0, 0});
    a.emplace<Velocity>(ea, glm::dvec3{0, 1, 0});
    b.emplace<Velocity>(eb, glm::dvec3{0, 1, 0});
    b.emplace<Position>(eb, glm::dvec3{1, 0, 0});
    EXPECT_EQ(a.state_hash(), b.state_hash());
}

TEST(Registry, StateHashSeesTheSmallestChange) {
    Registry r;
    const Entity e = r.create();
    r.emplace<Position>(e, glm::dvec3{1, 0, 0});
    const auto before = r.state_hash();
    r.get<Position>(e).value.x = std::nextafter(1.0, 2.0);
    EXPECT_NE(before, r.state_hash());
}

TEST(Registry, SingleFindsTheOneEntityWithAComponent) {
    Registry r;
    EXPECT_EQ(r.single<Position>(), nullptr);
    r.create();
    const Entity e = r.create();
    r.emplace<Position>(e, glm::dvec3{4, 5, 6});
    ASSERT_NE(r.single<Position>(), nullptr);
    EXPECT_EQ(r.single<Position>()->value.z, 6.0);
}

namespace {
struct Counter {
    int ticks = 0;
};
struct Scratch { // what a system makes at its first firing
    int made = 1;
};
struct Unmovable {
    Unmovable() = default;
    Unmovable(const Unmovable&) = delete;
    Unmovable& operator=(const Unmovable&) = delete;
};
} // namespace

// A replay's snapshot: entities, components and resources go back to what was saved, in the registry
// saved or in another built the same way (a resource made since goes; one it lacks is made); a port
// keeps the target of the registry it is in.
TEST(Registry, ASavedRegistryComesBackAsItWasAndAPortKeepsItsOwnTarget) {
    int here = 0, there = 0;
    Registry r;
    r.set_resource<Counter>(Counter{3});
    r.set_resource<Port<int>>(here);
    const Entity a = r.create();
    r.emplace<Position>(a, glm::dvec3{1, 2, 3});
    r.emplace<Frozen>(a);
    const Entity b = r.create();
    r.emplace<Velocity>(b, glm::dvec3{0, 0, 1});
    const auto hash = r.state_hash();
    auto saved = r.save();
    ASSERT_TRUE(saved.ok()) << saved.error().message;

    // Everything changes after the save: a component, a resource, an entity gone, one made.
    r.get<Position>(a).value.x = 9.0;
    r.resource<Counter>()->ticks = 7;
    r.destroy(b);
    const Entity c = r.create();
    r.emplace<Velocity>(c, glm::dvec3{5, 5, 5});
    r.set_resource<Scratch>();
    ASSERT_NE(r.state_hash(), hash);
    r.restore(*saved);
    EXPECT_EQ(r.resource<Scratch>(), nullptr) << "made after the save, it goes";
    EXPECT_EQ(r.state_hash(), hash);
    EXPECT_EQ(r.get<Position>(a).value.x, 1.0);
    EXPECT_TRUE(r.all_of<Frozen>(a));
    EXPECT_TRUE(r.valid(b));
    EXPECT_FALSE(r.valid(c));
    EXPECT_EQ(r.resource<Counter>()->ticks, 3);
    EXPECT_EQ(r.alive(), 2u);
    EXPECT_NE(r.create().index, b.index) << "b's slot is b's again, not free";

    // Into another registry built the same way: its own port stays its own.
    Registry other;
    other.set_resource<Port<int>>(there);
    other.restore(*saved);
    ASSERT_NE(other.resource<Counter>(), nullptr) << "a saved resource it lacked is made";
    EXPECT_EQ(other.state_hash(), hash);
    EXPECT_EQ(other.resource<Counter>()->ticks, 3);
    EXPECT_EQ(&other.resource<Port<int>>()->use(), &there);
    // Restored twice, the same.
    other.get<Position>(a).value.y = -1.0;
    other.restore(*saved);
    EXPECT_EQ(other.state_hash(), hash);
}

TEST(Registry, AResourceThatCannotBeCopiedIsNamedAndNothingIsSaved) {
    Registry r;
    r.set_resource<Unmovable>();
    const auto saved = r.save();
    ASSERT_FALSE(saved.ok());
    EXPECT_NE(saved.error().message.find("resource '"), std::string::npos) << saved.error().message;
    EXPECT_NE(saved.error().message.find("Unmovable' cannot be copied"), std::string::npos) << saved.error().message;
}
