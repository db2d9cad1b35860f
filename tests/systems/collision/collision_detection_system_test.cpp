#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/kenzan.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/collision/collision_detection_system.hpp"
#include "systems/collision/narrow_phase.hpp"
#include "systems/collision/spread_collision_system.hpp"

using namespace ikebana;
using namespace ikebana::components;

namespace {
Collider sphere(glm::dvec3 c, double r) { return {ShapeKind::sphere, c, c, r, glm::dvec3{0.0}}; }
Collider capsule(glm::dvec3 a, glm::dvec3 b, double r) { return {ShapeKind::capsule, a, b, r, glm::dvec3{0.0}}; }

template <typename Tag>
ecs::Entity add(ecs::Registry& r, Collider c) {
    const auto e = r.create();
    r.emplace<Collider>(e, c);
    r.emplace<Tag>(e);
    return e;
}

const Contacts& detect(ecs::Registry& r) {
    systems::CollisionDetectionSystem system;
    sched::SystemContext ctx{r, 0, 0.0625, 0};
    system(ctx);
    return *r.resource<Contacts>();
}

Kenzan standard_kenzan() {
    Kenzan k{};
    k.layout = "test";
    k.origin_m = {0, 0, 0};
    k.pitch_m = 0.004;
    k.columns = 20;
    k.rows = 20;
    k.pin = {0.0009, 0.011, 0.0015};
    k.base_thickness_m = 0.008;
    return k;
}
} // namespace

TEST(CollisionDetection, ActiveAgainstPassiveGivesContactWithDepthAndNormal) {
    ecs::Registry r;
    const auto a = add<ActiveCollider>(r, sphere({0, 0, 0.015}, 0.01));
    const auto b = add<PassiveCollider>(r, sphere({0, 0, 0}, 0.01));
    const auto& c = detect(r);
    ASSERT_EQ(c.list.size(), 1u);
    EXPECT_EQ(c.list[0].a, a);
    EXPECT_EQ(c.list[0].b, b);
    EXPECT_NEAR(c.list[0].depth_m, 0.005, 1e-12);
    EXPECT_NEAR(c.list[0].normal.z, 1.0, 1e-12);
    EXPECT_EQ(c.list[0].pin, -1);
}

TEST(CollisionDetection, InactivePartsNeverProduceContacts) {
    ecs::Registry r;
    add<ActiveCollider>(r, sphere({0, 0, 0}, 0.01));
    for (int i = 0; i < 50; ++i) add<InactiveCollider>(r, sphere({0, 0, 0.001 * i}, 0.01));
    const auto& c = detect(r);
    EXPECT_TRUE(c.list.empty());
    EXPECT_EQ(c.pairs_tested, 0u) << "inactive parts are not even candidates";
}

TEST(CollisionDetection, PassivePairsAreNeverTested) {
    ecs::Registry r;
    add<PassiveCollider>(r, sphere({0, 0, 0}, 0.01));
    add<PassiveCollider>(r, sphere({0, 0, 0.005}, 0.01));
    const auto& c = detect(r);
    EXPECT_TRUE(c.list.empty());
    EXPECT_EQ(c.pairs_tested, 0u);
}

TEST(CollisionDetection, ActivePairsAreReportedOnce) {
    ecs::Registry r;
    add<ActiveCollider>(r, sphere({0, 0, 0}, 0.01));
    add<ActiveCollider>(r, sphere({0, 0, 0.01}, 0.01));
    EXPECT_EQ(detect(r).list.size(), 1u);
}

TEST(CollisionDetection, PartsOfOneFlowerDoNotCollide) {
    ecs::Registry r;
    const auto flower = r.create();
    const auto a = add<ActiveCollider>(r, capsule({0, 0, 0}, {0, 0, 0.01}, 0.004));
    const auto b = add<PassiveCollider>(r, capsule({0, 0, 0.01}, {0, 0, 0.02}, 0.004));
    ecs::attach(r, a, flower);
    ecs::attach(r, b, flower);
    EXPECT_TRUE(detect(r).list.empty());
}

TEST(CollisionDetection, FarApartCollidersAreNotTested) {
    ecs::Registry r;
    add<ActiveCollider>(r, sphere({0, 0, 0}, 0.01));
    add<PassiveCollider>(r, sphere({1.0, 0, 0}, 0.01));
    EXPECT_EQ(detect(r).pairs_tested, 0u) << "the spatial hash kept them apart";
}

TEST(CollisionDetection, StemEndPushedIntoKenzanMeetsThePinsUnderIt) {
    ecs::Registry r;
    const auto kenzan = r.create();
    r.emplace<Kenzan>(kenzan, standard_kenzan());
    r.emplace<PassiveCollider>(kenzan);
    // A 7.5 mm stem, vertical, centred between four pins (pitch 4 mm, grid of even size: pins at
    // +-2 mm), bottom 5 mm above the base plate: those four pins are inside its footprint.
    const auto stem = add<ActiveCollider>(r, capsule({0, 0, 0.005}, {0, 0, 0.05}, 0.00375));
    const auto& c = detect(r);
    std::set<std::int32_t> pins;
    for (const auto& contact : c.list) {
        EXPECT_EQ(contact.a, stem);
        EXPECT_EQ(contact.b, kenzan);
        EXPECT_GT(contact.depth_m, 0.0);
        pins.insert(contact.pin);
    }
    EXPECT_EQ(pins.size(), 4u);
    EXPECT_LE(c.pairs_tested, 16u) << "the grid limits candidates to the pins under the stem";
}

TEST(CollisionDetection, AstronomicalAndNonFiniteCoordinatesEndAtOnce) {
    // A double of 1e15 does not change when 1 is added: the grid loop once stepped it forever.
    ecs::Registry r;
    for (const double far : {2.8e14, 1e15, 1e18, 1e300, -1e300}) {
        add<ActiveCollider>(r, sphere({far, 0, 0}, 0.01));
        add<ActiveCollider>(r, capsule({0, far, 0}, {0, far, 0.01}, 0.004));
        add<PassiveCollider>(r, sphere({0, 0, far}, 0.01));
    }
    add<ActiveCollider>(r, sphere({std::numeric_limits<double>::quiet_NaN(), 0, 0}, 0.01));
    add<ActiveCollider>(r, sphere({std::numeric_limits<double>::infinity(), 0, 0}, 0.01));
    const auto k = r.create();
    r.emplace<Kenzan>(k, standard_kenzan());
    r.emplace<PassiveCollider>(k);
    const auto near = add<ActiveCollider>(r, sphere({0, 0, 0.5}, 0.01));
    const auto other = add<PassiveCollider>(r, sphere({0, 0, 0.515}, 0.01));
    const auto& c = detect(r);
    ASSERT_EQ(c.list.size(), 1u) << "the ordinary pair is still found among the far ones";
    EXPECT_EQ(c.list[0].a, near);
    EXPECT_EQ(c.list[0].b, other);
}

TEST(CollisionDetection, PinRangesAreEmptyForBoundsOffTheKenzanOrNotANumber) {
    const auto k = standard_kenzan();
    const auto none = k.pins_within({1e300, 1e300}, {1e300, 1e300});
    EXPECT_GT(none.column_lo, none.column_hi);
    const auto nan = k.pins_within({std::nan(""), 0}, {std::nan(""), 0});
    EXPECT_GT(nan.column_lo, nan.column_hi);
    const auto all = k.pins_within({-1e300, -1e300}, {1e300, 1e300});
    EXPECT_EQ(all.column_lo, 0);
    EXPECT_EQ(all.column_hi, 19);
    EXPECT_EQ(all.row_hi, 19);
}

// The cell index holds only the Active colliders, and every collider looks itself up in it: what it
// finds is what testing every Active collider against every other collider finds, pair for pair and in
// the same order (Active collider by Active collider, partners by index), with the Active pairs once,
// including large colliders spanning many cells and colliders of one owner left alone.
TEST(CollisionDetection, TheIndexOfActiveCollidersFindsWhatTestingEveryPairFinds) {
    ecs::Registry r;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-0.06, 0.06);
    std::vector<std::pair<ecs::Entity, Collider>> actives, passives;
    const auto owner = r.create();
    for (int i = 0; i < 30; ++i) {
        const Collider c = i % 3 ? sphere({u(rng), u(rng), u(rng)}, 0.004 + 0.01 * (i % 4 == 0))
                                 : capsule({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, 0.003);
        const auto e = add<ActiveCollider>(r, c);
        if (i < 4) r.emplace<ecs::ChildOf>(e, ecs::ChildOf{owner}); // parts of one flower
        actives.emplace_back(e, c);
    }
    for (int i = 0; i < 150; ++i) {
        const Collider c = i == 0 ? sphere({0, 0, 0}, 0.05) : sphere({u(rng), u(rng), u(rng)}, 0.005); // one spans many cells
        const auto e = add<PassiveCollider>(r, c);
        if (i < 3) r.emplace<ecs::ChildOf>(e, ecs::ChildOf{owner});
        passives.emplace_back(e, c);
    }
    const Contacts& contacts = detect(r);
    std::vector<std::pair<ecs::Entity, ecs::Entity>> expected;
    const auto owner_of = [&](ecs::Entity e) {
        const auto* link = r.try_get<const ecs::ChildOf>(e);
        return link ? link->parent : e;
    };
    for (std::size_t i = 0; i < actives.size(); ++i) {
        const auto test = [&](const std::pair<ecs::Entity, Collider>& other) {
            if (owner_of(other.first) == owner_of(actives[i].first)) return;
            if (systems::collision::collide(actives[i].second, other.second)) expected.emplace_back(actives[i].first, other.first);
        };
        for (std::size_t j = i + 1; j < actives.size(); ++j) test(actives[j]);
        for (const auto& p : passives) test(p);
    }
    ASSERT_GT(expected.size(), 15u);
    ASSERT_EQ(contacts.list.size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
        EXPECT_EQ(contacts.list[k].a, expected[k].first) << k;
        EXPECT_EQ(contacts.list[k].b, expected[k].second) << k;
    }
    EXPECT_LT(contacts.pairs_tested, 30u * 179u / 4u) << "the grid leaves far pairs untested";
}

// The pass spread over the ticks after a collider update finds what the whole pass finds, contact for
// contact in the same order, and no tick does more than a share of the pair tests; until it is done the
// previous pass's contacts stay.
TEST(CollisionDetection, APassSpreadOverTicksFindsWhatTheWholePassFinds) {
    ecs::Registry r;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    for (int i = 0; i < 40; ++i) add<ActiveCollider>(r, sphere({u(rng), u(rng), 0.02 + u(rng)}, 0.006));
    for (int i = 0; i < 200; ++i) add<PassiveCollider>(r, sphere({u(rng), u(rng), 0.02 + u(rng)}, 0.006));
    for (int i = 0; i < 6; ++i) add<ActiveCollider>(r, capsule({0.002 * i, 0.001, 0.004}, {0.002 * i, 0.001, 0.05}, 0.0037));
    const auto k = r.create();
    r.emplace<Kenzan>(k, standard_kenzan());
    const Contacts whole = detect(r);
    ASSERT_GT(whole.list.size(), 20u);

    r.resource<Contacts>()->list.clear();
    r.set_resource<ColliderPass>().generation = 1; // an update happened
    systems::SpreadCollisionSystem spread;
    int ticks = 0;
    std::uint64_t most_pairs_a_tick = 0;
    for (; ticks < 40 && r.resource<Contacts>()->list.empty(); ++ticks) {
        const auto before = systems::collision_pass::of(r).pairs_tested;
        sched::SystemContext ctx{r, 1000 * ticks, 0.001, 0};
        spread(ctx);
        const auto& pass = systems::collision_pass::of(r);
        // The world's one pass state: the whole pass above left its count, which the spread pass's start resets.
        const auto this_tick = pass.pairs_tested >= before ? pass.pairs_tested - before : pass.pairs_tested;
        if (pass.step > 0) most_pairs_a_tick = std::max(most_pairs_a_tick, this_tick);
    }
    const Contacts& spread_contacts = *r.resource<Contacts>();
    EXPECT_EQ(ticks, static_cast<int>(spread.gather_slices + spread.slices) + 3) << "the update's tick, the index, the gathers, the slices, the pins";
    ASSERT_EQ(spread_contacts.list.size(), whole.list.size());
    for (std::size_t i = 0; i < whole.list.size(); ++i) {
        EXPECT_EQ(spread_contacts.list[i].a, whole.list[i].a) << i;
        EXPECT_EQ(spread_contacts.list[i].b, whole.list[i].b) << i;
        EXPECT_EQ(spread_contacts.list[i].pin, whole.list[i].pin) << i;
        EXPECT_EQ(spread_contacts.list[i].depth_m, whole.list[i].depth_m) << i;
    }
    EXPECT_EQ(spread_contacts.pairs_tested, whole.pairs_tested);
    EXPECT_LT(most_pairs_a_tick, whole.pairs_tested / 2) << "no tick does the pass's work";
}

// Collider updates faster than a spread pass takes (a changed rate): passes run back to back and each
// hands its contacts over; none is restarted for ever.
TEST(CollisionDetection, UpdatesFasterThanASpreadPassStillGiveContacts) {
    ecs::Registry r;
    add<ActiveCollider>(r, sphere({0, 0, 0.015}, 0.01));
    add<PassiveCollider>(r, sphere({0, 0, 0}, 0.01));
    auto& update = r.set_resource<ColliderPass>();
    systems::SpreadCollisionSystem spread;
    r.set_resource<Contacts>();
    int published = 0;
    for (int tick = 0; tick < 200; ++tick) {
        if (tick % 10 == 0) ++update.generation; // every 10 ticks, a pass takes 16
        const auto before = r.resource<Contacts>()->list.size();
        r.resource<Contacts>()->list.clear();
        sched::SystemContext ctx{r, 1000 * tick, 0.001, 0};
        spread(ctx);
        if (!r.resource<Contacts>()->list.empty()) ++published;
        (void)before;
    }
    EXPECT_GE(published, 10) << "a pass every 16 ticks or so";
}

// A spread pass keeps what it took and found from tick to tick. That state was once kept in the system
// object, outside the registry: two worlds in different places of a pass had one state hash, and a
// world rebuilt from its registry lost the pass. It is the registry's CollisionPass now.
TEST(CollisionDetection, APassInProgressIsPartOfTheWorldsStateHash) {
    ecs::Registry r;
    add<ActiveCollider>(r, sphere({0, 0, 0.015}, 0.01));
    add<PassiveCollider>(r, sphere({0, 0, 0}, 0.01));
    r.set_resource<ColliderPass>().generation = 1;
    r.set_resource<Contacts>();
    systems::SpreadCollisionSystem spread;
    std::vector<std::uint64_t> hashes;
    for (int tick = 0; tick < 4; ++tick) {
        sched::SystemContext ctx{r, 1000 * tick, 0.001, 0};
        spread(ctx);
        hashes.push_back(r.state_hash());
    }
    EXPECT_NE(hashes[0], hashes[1]) << "taking the colliders changes the state";
    EXPECT_NE(hashes[1], hashes[2]) << "each slice changes the state";
    EXPECT_EQ(r.count<CollisionPass>(), 1u) << "one pass state per world";
}
