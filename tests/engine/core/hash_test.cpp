#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "engine/core/hash.hpp"

using namespace ikebana;

namespace {
struct Inner {
    float a;
    int b;
};
struct Outer {
    glm::dvec3 position;
    std::vector<double> masses;
    std::string name;
    Inner inner;
    std::optional<int> maybe;
};
std::uint64_t digest(const Outer& o) {
    StateHasher h;
    hash_value(h, o);
    return h.digest();
}
} // namespace

TEST(StateHash, AggregateFieldsAreCounted) {
    static_assert(detail::field_count<Inner>() == 2);
    static_assert(detail::field_count<Outer>() == 5);
}

TEST(StateHash, EqualValuesHashEqual) {
    const Outer a{{1, 2, 3}, {0.5, 0.25}, "stem", {1.5f, 2}, 4};
    const Outer b = a;
    EXPECT_EQ(digest(a), digest(b));
}

TEST(StateHash, EveryFieldMatters) {
    const Outer base{{1, 2, 3}, {0.5, 0.25}, "stem", {1.5f, 2}, 4};
    std::vector<Outer> changed(6, base);
    changed[0].position.z = 3.0000001;
    changed[1].masses.push_back(0.0);
    changed[2].name = "Stem";
    changed[3].inner.a = -1.5f;
    changed[4].inner.b = 3;
    changed[5].maybe.reset();
    for (const auto& c : changed) EXPECT_NE(digest(c), digest(base));
}

TEST(StateHash, NegativeZeroDiffersFromZero) {
    StateHasher a;
    StateHasher b;
    hash_value(a, 0.0);
    hash_value(b, -0.0);
    EXPECT_NE(a.digest(), b.digest());
}
