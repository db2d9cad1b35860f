#include <gtest/gtest.h>

#include <set>

#include "engine/ecs/registry.hpp"

using namespace ikebana::ecs;

namespace {
struct A {
    int value = 0;
};
struct B {
    int value = 0;
};
struct Hidden {};
} // namespace

TEST(View, VisitsExactlyTheEntitiesWithAllComponents) {
    Registry r;
    std::set<std::uint32_t> expected;
    for (int i = 0; i < 100; ++i) {
        const Entity e = r.create();
        if (i % 2 == 0) r.emplace<A>(e, i);
        if (i % 3 == 0) r.emplace<B>(e, -i);
        if (i % 6 == 0) expected.insert(e.index);
    }
    std::set<std::uint32_t> seen;
    r.view<A, B>().each([&](Entity e, A& a, B& b) {
        EXPECT_EQ(a.value, -b.value);
        seen.insert(e.index);
    });
    EXPECT_EQ(seen, expected);
}

TEST(View, TagsFilterWithoutBeingPassed) {
    Registry r;
    const Entity e1 = r.create();
    const Entity e2 = r.create();
    r.emplace<A>(e1, 1);
    r.emplace<A>(e2, 2);
    r.emplace<Hidden>(e2);
    int sum = 0;
    r.view<A, Hidden>().each([&](Entity, A& a) { sum += a.value; });
    EXPECT_EQ(sum, 2);
}

TEST(View, ExcludeSkipsEntities) {
    Registry r;
    const Entity e1 = r.create();
    const Entity e2 = r.create();
    r.emplace<A>(e1, 1);
    r.emplace<A>(e2, 2);
    r.emplace<Hidden>(e2);
    int sum = 0;
    r.view<A>(exclude<Hidden>).each([&](Entity, A& a) { sum += a.value; });
    EXPECT_EQ(sum, 1);
}

TEST(View, ComponentNobodyHasGivesEmptyView) {
    Registry r;
    r.emplace<A>(r.create());
    EXPECT_EQ((r.view<A, B>().size()), 0u);
}

TEST(View, WritesThroughReferences) {
    Registry r;
    const Entity e = r.create();
    r.emplace<A>(e, 1);
    r.view<A>().each([](Entity, A& a) { a.value = 42; });
    EXPECT_EQ(r.get<A>(e).value, 42);
}

TEST(View, StructuralChangeDuringIterationIsRefused) {
    Registry r;
    const Entity e = r.create();
    r.emplace<A>(e, 1);
    EXPECT_THROW(r.view<A>().each([&](Entity x, A&) { r.destroy(x); }), std::logic_error);
    EXPECT_THROW(r.view<A>().each([&](Entity x, A&) { r.emplace<B>(x); }), std::logic_error);
    EXPECT_THROW(r.view<A>().each([&](Entity x, A&) { r.remove<A>(x); }), std::logic_error);
    EXPECT_FALSE(r.iterating()) << "the guard is released when iteration throws";
    EXPECT_TRUE(r.valid(e));
}
