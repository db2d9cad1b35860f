#include <gtest/gtest.h>

#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/insertion/insertion_tracking_system.hpp"
#include "systems/physics/stem_builder.hpp"

using namespace ikebana;
using namespace ikebana::components;

namespace {
// Inserts one stem `times` times by moving it in and out of the pins while held, through the
// tracking system; returns the insertion at which the bottom broke (0: never).
struct Bench {
    ecs::Registry r;
    ecs::Entity flower;
    systems::InsertionTrackingSystem tracking;
    explicit Bench(std::uint64_t seed, std::vector<double> hazard) {
        const auto k = r.create();
        r.emplace<Kenzan>(k, Kenzan{"t", {0, 0, 0}, 0.004, 20, 20, {0.0009, 0.0115, 0.0015}, 0.008, 0.0});
        r.emplace<RandomStream>(r.create(), seed);
        systems::physics::StemSpec spec;
        spec.base_m = {0, 0, 0.05};
        auto stem = systems::physics::build_stem(spec);
        flower = r.create();
        r.emplace<StemPoints>(flower, stem.points);
        r.emplace<StemRestShape>(flower, stem.rest);
        PinResistance model{};
        model.break_probability_by_insertion = std::move(hazard);
        r.emplace<PinResistance>(flower, model);
        r.emplace<InsertionHistory>(flower);
        r.emplace<PinEngagement>(flower);
        r.emplace<Grasp>(flower, std::uint8_t{1});
    }
    std::int64_t now_us = 0;
    // Each move takes `after_us` (a trainee's hand: a tenth of a second).
    void move_bottom_to(double z, std::int64_t after_us = 100'000) {
        auto& x = r.get<StemPoints>(flower).position_m;
        const double dz = z - x[0].z;
        for (auto& p : x) p.z += dz;
        now_us += after_us;
        sched::SystemContext ctx{r, now_us, 0.001, 0};
        tracking(ctx);
    }
    std::uint32_t insert_until_break(std::uint32_t limit) {
        for (std::uint32_t n = 1; n <= limit; ++n) {
            move_bottom_to(0.005);
            move_bottom_to(0.05);
            if (r.get<InsertionHistory>(flower).bottom_broken) return n;
        }
        return 0;
    }
};
} // namespace

TEST(Breakage, EachEntryIntoThePinsIsOneInsertion) {
    Bench b(1, {});
    for (int i = 0; i < 5; ++i) {
        b.move_bottom_to(0.005);
        b.move_bottom_to(0.004); // moving while inside is the same insertion
        b.move_bottom_to(0.05);
    }
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 5u);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).records.size(), 5u);
}

TEST(Breakage, StemThatIsNotHeldDoesNotCountAnInsertion) {
    Bench b(1, {});
    b.r.get<Grasp>(b.flower).hands = 0;
    b.move_bottom_to(0.005);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 0u);
    EXPECT_TRUE(b.r.get<PinEngagement>(b.flower).in_kenzan);
}

// A hand puts the stem's end just into the pins (less than pierced) and lets go; its weight takes it the
// rest of the way. The hand put it there: one insertion (a trainee's cherry stood in the kenzan with
// "insertions 0"). A stem that was never held in this entry still counts none (above).
TEST(Breakage, AStemPlacedByHandThatSinksInAfterTheHandLetGoIsOneInsertion) {
    Bench b(1, {});
    const double top = b.r.single<Kenzan>()->pin_height_m();
    b.move_bottom_to(top - 0.001); // in the pins, not yet pierced
    EXPECT_TRUE(b.r.get<PinEngagement>(b.flower).in_kenzan);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 0u);
    b.r.get<Grasp>(b.flower).hands = 0;
    b.move_bottom_to(top - 0.006);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 1u);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions_total, 1u);
    b.move_bottom_to(top - 0.008); // sinking further is the same insertion
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 1u);
}

// Hazards 0.2, 0.4, then 0.6 per insertion: E[N] = 0.2*1 + 0.8*0.4*2 + 0.8*0.6*(3 + 0.4/0.6) = 2.6,
// the paper's mean. Over 4000 flowers the sample mean is within 0.1 of it.
TEST(Breakage, MeanInsertionsToBreakMatchesTheHazards) {
    double total = 0.0;
    const int flowers = 4000;
    for (int f = 0; f < flowers; ++f) {
        Bench b(static_cast<std::uint64_t>(f) * 7919 + 1, {0.2, 0.4, 0.6});
        const auto n = b.insert_until_break(100);
        ASSERT_GT(n, 0u);
        total += n;
    }
    EXPECT_NEAR(total / flowers, 2.6, 0.1);
}

TEST(Breakage, SameSeedBreaksAtTheSameInsertion) {
    for (std::uint64_t seed = 1; seed < 30; ++seed) {
        Bench a(seed, {0.2, 0.4, 0.6});
        Bench b(seed, {0.2, 0.4, 0.6});
        EXPECT_EQ(a.insert_until_break(100), b.insert_until_break(100));
    }
}

TEST(Breakage, ReusedHoleIsRecorded) {
    Bench b(1, {});
    b.move_bottom_to(0.005);
    b.move_bottom_to(0.05);
    b.move_bottom_to(0.005);
    const auto& records = b.r.get<InsertionHistory>(b.flower).records;
    ASSERT_EQ(records.size(), 2u);
    EXPECT_FALSE(records[0].reused_hole);
    EXPECT_TRUE(records[1].reused_hole);
}


// Out of the pins for a tick or two and back (a grab unbending the stem, numerical jitter) is the same
// insertion; out for longer than the tracker's minimum is a new one.
TEST(Breakage, AMomentOutOfThePinsIsNotANewInsertion) {
    Bench b(1, {});
    b.move_bottom_to(0.005);
    b.move_bottom_to(0.05, 1'000);
    b.move_bottom_to(0.005, 1'000);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 1u);
    b.move_bottom_to(0.05);
    b.move_bottom_to(0.005, b.tracking.min_time_out_us);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 2u);
}

// An end lifted just over the tips that swings back into them (a stem pulled out in jerks) is the same
// insertion, however long the swing; one lifted clear of them and pushed back is a new one, and so is
// one that hovered over the tips for half a second before going back in.
TEST(Breakage, AnEndThatHoveredOverTheTipsAndSwungBackIsNotANewInsertion) {
    Bench b(1, {});
    const double tips_m = b.r.single<const Kenzan>()->pin_height_m();
    b.move_bottom_to(0.005);
    b.move_bottom_to(tips_m + 0.003);
    b.move_bottom_to(tips_m - 0.003);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 1u) << "3 mm over the tips for 0.1 s";
    b.move_bottom_to(tips_m + 0.003);
    b.move_bottom_to(tips_m - 0.003, b.tracking.min_time_hovering_us);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 2u) << "hovering for half a second";
    b.move_bottom_to(tips_m + b.tracking.min_rise_out_m + 0.001);
    b.move_bottom_to(tips_m - 0.003);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 3u) << "lifted clear of the tips";
}

// An end that slid off the pins sideways below the tips and went back in a centimetre away is a new
// insertion: a new place, though it never rose over the tips.
TEST(Breakage, AnEndPutBackElsewhereBelowTheTipsIsANewInsertion) {
    Bench b(1, {});
    b.move_bottom_to(0.005);
    auto& x = b.r.get<StemPoints>(b.flower).position_m;
    for (auto& p : x) p.x += 0.2; // off the kenzan, at the same height
    b.move_bottom_to(0.005);
    for (auto& p : x) p.x -= 0.2 - 0.01; // back, 1 cm from where it left
    b.move_bottom_to(0.005);
    EXPECT_EQ(b.r.get<InsertionHistory>(b.flower).insertions, 2u);
}
