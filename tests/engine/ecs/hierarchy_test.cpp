#include <gtest/gtest.h>

#include "engine/ecs/registry.hpp"

using namespace ikebana::ecs;

TEST(Hierarchy, DestroyingParentDestroysWhatItOwns) {
    Registry r;
    const Entity flower = r.create();
    const Entity stem = r.create();
    const Entity leaf = r.create();
    const Entity vein = r.create();
    attach(r, stem, flower);
    attach(r, leaf, flower);
    attach(r, vein, leaf);
    EXPECT_EQ(children_of(r, flower).size(), 2u);
    EXPECT_EQ(parent_of(r, vein), leaf);
    r.destroy(flower);
    EXPECT_FALSE(r.valid(stem));
    EXPECT_FALSE(r.valid(leaf));
    EXPECT_FALSE(r.valid(vein));
    EXPECT_EQ(r.alive(), 0u);
}

TEST(Hierarchy, DestroyingChildUpdatesParentList) {
    Registry r;
    const Entity flower = r.create();
    const Entity a = r.create();
    const Entity b = r.create();
    attach(r, a, flower);
    attach(r, b, flower);
    r.destroy(a);
    ASSERT_EQ(children_of(r, flower).size(), 1u);
    EXPECT_EQ(children_of(r, flower)[0], b);
}

TEST(Hierarchy, ReattachMovesChild) {
    Registry r;
    const Entity p1 = r.create();
    const Entity p2 = r.create();
    const Entity c = r.create();
    attach(r, c, p1);
    attach(r, c, p2);
    EXPECT_TRUE(children_of(r, p1).empty());
    EXPECT_EQ(parent_of(r, c), p2);
}

TEST(Hierarchy, CyclesAreRefused) {
    Registry r;
    const Entity a = r.create();
    const Entity b = r.create();
    attach(r, b, a);
    EXPECT_THROW(attach(r, a, b), std::logic_error);
    EXPECT_THROW(attach(r, a, a), std::logic_error);
}
