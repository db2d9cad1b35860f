#include <gtest/gtest.h>

#include "engine/ecs/port.hpp"
#include "engine/ecs/registry.hpp"
#include "engine/sched/schedule.hpp"

using namespace ikebana;
using namespace ikebana::sched;

namespace {
struct Springs {};
struct Points {};

SystemDesc make(std::string name, std::string phase, std::vector<std::string> reads, std::vector<std::string> writes,
                std::vector<std::string> after = {}, std::string rate = "haptic") {
    SystemDesc d;
    d.name = std::move(name);
    d.lane = "sim";
    d.phase = std::move(phase);
    d.rate = std::move(rate);
    d.reads = std::move(reads);
    d.writes = std::move(writes);
    d.after = std::move(after);
    d.run = [](SystemContext&) {};
    return d;
}

struct Fixture {
    ecs::Registry registry;
    Schedule schedule;
    Fixture() {
        EXPECT_TRUE(schedule.add_lane({"sim", &registry, LaneThread::caller, {"input", "physics", "output"}}));
    }
};
} // namespace

TEST(Schedule, WritersWithoutOrderAreReportedAtStartUp) {
    Fixture f;
    ASSERT_TRUE(f.schedule.add(make("springs", "physics", {}, components<Points>())));
    ASSERT_TRUE(f.schedule.add(make("contacts", "physics", {}, components<Points>())));
    const auto result = f.schedule.finalize();
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().code, ErrorCode::schedule_conflict);
    EXPECT_NE(result.error().message.find("'springs' and 'contacts'"), std::string::npos) << result.error().message;
    EXPECT_NE(result.error().message.find("Points"), std::string::npos) << result.error().message;
}

TEST(Schedule, ReaderAndWriterWithoutOrderAreReported) {
    Fixture f;
    ASSERT_TRUE(f.schedule.add(make("springs", "physics", {}, components<Points>())));
    ASSERT_TRUE(f.schedule.add(make("force_out", "physics", components<Points>(), {})));
    EXPECT_FALSE(f.schedule.finalize());
}

TEST(Schedule, AfterResolvesTheConflictAndFixesTheOrder) {
    Fixture f;
    ASSERT_TRUE(f.schedule.add(make("b", "physics", {}, components<Points>(), {"a"})));
    ASSERT_TRUE(f.schedule.add(make("a", "physics", {}, components<Points>())));
    ASSERT_TRUE(f.schedule.finalize());
    ASSERT_EQ(f.schedule.systems().size(), 2u);
    EXPECT_EQ(f.schedule.systems()[0].desc.name, "a");
    EXPECT_EQ(f.schedule.systems()[1].desc.name, "b");
}

TEST(Schedule, PhasesOrderSystemsWithoutConflict) {
    Fixture f;
    ASSERT_TRUE(f.schedule.add(make("force_out", "output", components<Points>(), {})));
    ASSERT_TRUE(f.schedule.add(make("springs", "physics", {}, components<Points, Springs>())));
    ASSERT_TRUE(f.schedule.add(make("read_devices", "input", {}, {})));
    ASSERT_TRUE(f.schedule.finalize());
    EXPECT_EQ(f.schedule.systems()[0].desc.name, "read_devices");
    EXPECT_EQ(f.schedule.systems()[1].desc.name, "springs");
    EXPECT_EQ(f.schedule.systems()[2].desc.name, "force_out");
}

TEST(Schedule, CyclesAndUnknownAfterAreReported) {
    Fixture f;
    ASSERT_TRUE(f.schedule.add(make("a", "physics", {}, {}, {"b"})));
    ASSERT_TRUE(f.schedule.add(make("b", "physics", {}, {}, {"a"})));
    ASSERT_TRUE(f.schedule.add(make("c", "physics", {}, {}, {"nope"})));
    const auto result = f.schedule.finalize();
    ASSERT_FALSE(result);
    EXPECT_NE(result.error().message.find("cycle"), std::string::npos);
    EXPECT_NE(result.error().message.find("'nope'"), std::string::npos);
}

TEST(Schedule, UnknownLanePhaseOrRateIsRefused) {
    Fixture f;
    auto bad_lane = make("x", "physics", {}, {});
    bad_lane.lane = "nowhere";
    EXPECT_FALSE(f.schedule.add(bad_lane));
    EXPECT_FALSE(f.schedule.add(make("y", "render", {}, {})));
    const auto r = f.schedule.add(make("z", "physics", {}, {}, {}, "warp"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("haptic"), std::string::npos) << "lists the known rates";
}

TEST(Schedule, DuplicateNamesAreRefused) {
    Fixture f;
    ASSERT_TRUE(f.schedule.add(make("a", "physics", {}, {})));
    EXPECT_FALSE(f.schedule.add(make("a", "input", {}, {})));
}

TEST(RateTable, PaperDefaults) {
    const auto t = RateTable::paper_defaults();
    EXPECT_EQ(t.hz("haptic"), 1000.0);
    EXPECT_EQ(t.hz("position_estimate"), 100.0);
    EXPECT_EQ(t.hz("position_check"), 16.0);
    EXPECT_EQ(t.hz("render"), 30.0);
}

TEST(RateTable, BadValuesAreRefusedWithAClearMessage) {
    auto t = RateTable::paper_defaults();
    for (const char* bad : {"render=0", "render=-30", "render=abc", "render=", "render", "=30", "render=30x",
                            "render=nan", "render=inf", "render=1e9"}) {
        const auto r = t.set_from_string(bad);
        EXPECT_FALSE(r) << bad;
    }
    const auto unknown = t.set_from_string("warp=10");
    ASSERT_FALSE(unknown);
    EXPECT_EQ(unknown.error().code, ErrorCode::not_found);
    EXPECT_NE(unknown.error().message.find("warp"), std::string::npos);
    EXPECT_EQ(t.hz("render"), 30.0) << "a refused change leaves the old value";
    EXPECT_TRUE(t.set_from_string("render=60"));
    EXPECT_EQ(t.hz("render"), 60.0);
}

TEST(RateTable, RatesThatRoundToZeroMillihertzAreRefused) {
    // 1e-4 Hz is 0.1 mHz: the schedule would round it to 0 and divide by it (SIGFPE, issue 20).
    auto t = RateTable::paper_defaults();
    const auto tiny = t.set_from_string("render=1e-4");
    ASSERT_FALSE(tiny);
    EXPECT_EQ(tiny.error().message, "rate 'render' of 0.0001 Hz is below the supported minimum of 0.001 Hz");
    ASSERT_TRUE(t.set("render", min_rate_hz));
    ecs::Registry registry;
    Schedule schedule(t);
    ASSERT_TRUE(schedule.add_lane({"sim", &registry, LaneThread::caller, {"physics"}}));
    ASSERT_TRUE(schedule.add(make("slow", "physics", {}, {}, {}, "render")));
    ASSERT_TRUE(schedule.finalize());
    EXPECT_EQ(schedule.find("slow")->due_us(1), 1'000'000'000) << "the smallest allowed rate fires every 1000 s";
}

namespace {
struct Position {
    double x = 0.0;
};
struct Velocity {
    double v = 0.0;
};
struct Gravity {
    double g = 9.81;
};

// Where the systems below run: one lane, one phase, every tick.
struct OnThePhysicsPhase {
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "physics";
    static constexpr std::string_view rate = "haptic";
};

// Declares it reads Velocity, then writes it (a mutable view): the bug the check exists for.
struct WritesWhatItReads : OnThePhysicsPhase {
    static constexpr std::string_view name = "writes_what_it_reads";
    using reads = Components<Velocity>;
    using writes = Components<Position>;
    void operator()(SystemContext& ctx) {
        ctx.registry.view<Position, Velocity>().each([](ecs::Entity, Position& p, Velocity& v) { p.x += v.v; });
    }
};
// Reads a resource it never declared.
struct ReadsAnUndeclaredResource : OnThePhysicsPhase {
    static constexpr std::string_view name = "reads_an_undeclared_resource";
    using reads = Components<Velocity>;
    using writes = Components<Position>;
    void operator()(SystemContext& ctx) {
        const auto* g = ctx.registry.resource<const Gravity>();
        ctx.registry.view<Position, const Velocity>().each([&](ecs::Entity, Position& p, const Velocity& v) { p.x += v.v * g->g; });
    }
};
// Exactly what it declares: a const view of what it reads, a mutable one of what it writes.
struct DeclaresWhatItDoes : OnThePhysicsPhase {
    static constexpr std::string_view name = "declares_what_it_does";
    using reads = Components<Velocity, Gravity>;
    using writes = Components<Position>;
    void operator()(SystemContext& ctx) {
        const auto* g = ctx.registry.resource<const Gravity>();
        ctx.registry.view<Position, const Velocity>().each([&](ecs::Entity, Position& p, const Velocity& v) { p.x += v.v * g->g; });
    }
};

// Queues an emplace of what it declared only read: a deferred write is still its write.
struct QueuesAWriteOfWhatItReads : OnThePhysicsPhase {
    static constexpr std::string_view name = "queues_a_write";
    using reads = Components<Velocity>;
    using writes = Components<Position>;
    void operator()(SystemContext& ctx) {
        ctx.registry.view<Position>().each([&](ecs::Entity e, Position&) { ctx.registry.commands().emplace<Velocity>(e, Velocity{2.0}); });
    }
};
// Declares more than it does: reads Gravity and never looks at it, writes Velocity and only reads it.
struct DeclaresMoreThanItDoes : OnThePhysicsPhase {
    static constexpr std::string_view name = "declares_more";
    using reads = Components<Gravity>;
    using writes = Components<Position, Velocity>;
    void operator()(SystemContext& ctx) {
        ctx.registry.view<Position, const Velocity>().each([&](ecs::Entity, Position& p, const Velocity& v) { p.x += v.v; });
    }
};

// One entity with a Position and a Velocity, Gravity as a resource, and S alone in a schedule.
template <typename S>
struct OneSystem {
    ecs::Registry registry;
    Schedule schedule;
    OneSystem() {
        registry.set_resource<Gravity>();
        const auto e = registry.create();
        registry.emplace<Position>(e);
        registry.emplace<Velocity>(e, Velocity{1.0});
        EXPECT_TRUE(schedule.add_lane({"sim", &registry, LaneThread::caller, {"physics"}}));
        EXPECT_TRUE(schedule.add(describe(S{})));
        EXPECT_TRUE(schedule.finalize());
    }
};

template <typename S>
std::string first_firing_error() {
    OneSystem<S> one;
    auto& [registry, schedule] = one;
    try {
        schedule.systems()[0].fire(registry);
    } catch (const ecs::UndeclaredAccess& error) {
        EXPECT_EQ(registry.access_mask(), nullptr) << "the mask is cleared even when the system throws";
        return error.what();
    }
    EXPECT_EQ(registry.access_mask(), nullptr);
    return "";
}
} // namespace

// Declared access must be true: a system that writes what it declared read-only, or reads a resource it
// did not declare, is refused the moment it does so, naming itself and the type.
TEST(Schedule, RefusesUndeclaredComponentAccess) {
    EXPECT_EQ(first_firing_error<WritesWhatItReads>(),
              "system 'writes_what_it_reads' writes '{anonymous}::Velocity' without declaring it (declared read only: view it as const)");
    EXPECT_EQ(first_firing_error<ReadsAnUndeclaredResource>(), "system 'reads_an_undeclared_resource' reads '{anonymous}::Gravity' without declaring it");
    EXPECT_EQ(first_firing_error<DeclaresWhatItDoes>(), "") << "a system true to its declaration runs";
    EXPECT_EQ(first_firing_error<QueuesAWriteOfWhatItReads>(),
              "system 'queues_a_write' writes '{anonymous}::Velocity' without declaring it (declared read only: view it as const)")
        << "an emplace queued in the command buffer is checked as it is queued";
}

// Over-declaring is reported: a declaration the body never uses orders systems for nothing and hides
// the access that matters. Only systems that have fired are judged.
TEST(Schedule, ReportsDeclaredAccessTheSystemNeverUsed) {
    OneSystem<DeclaresMoreThanItDoes> more;
    auto& [registry, schedule] = more;
    EXPECT_TRUE(schedule.unused_access().empty()) << "a system that has not fired is not judged";
    schedule.systems()[0].fire(registry);
    const std::vector<std::string> expected{"system 'declares_more' declares writing '{anonymous}::Velocity' and only reads it",
                                            "system 'declares_more' declares reading '{anonymous}::Gravity' and never reads it"};
    EXPECT_EQ(schedule.unused_access(), expected);

    OneSystem<DeclaresWhatItDoes> exact;
    exact.schedule.systems()[0].fire(exact.registry);
    EXPECT_TRUE(exact.schedule.unused_access().empty()) << "a declaration that is all used says nothing";
}

// No pointer is a resource (a `T* const` read let a system write through it), and a Port's target is
// reached only from a non-const Port, that is, by a system that declared the Port written.
template <typename T>
concept HoldsAsResource = requires(ecs::Registry& r) { r.resource<T>(); };
static_assert(HoldsAsResource<Gravity> && HoldsAsResource<const Gravity>);
static_assert(!HoldsAsResource<Gravity*> && !HoldsAsResource<Gravity* const> && !HoldsAsResource<const Gravity*>);
template <typename P>
concept Usable = requires(P& p) { p.use(); };
static_assert(Usable<ecs::Port<Gravity>> && !Usable<const ecs::Port<Gravity>>);

TEST(Schedule, APortIsUsedOnlyByASystemThatDeclaredItWritten) {
    Gravity shared{};
    ecs::Registry registry;
    registry.set_resource<ecs::Port<Gravity>>(shared);
    registry.resource<ecs::Port<Gravity>>()->use().g = 2.0;
    EXPECT_EQ(shared.g, 2.0) << "the Port reaches what lives outside the registry";
    ecs::AccessMask reader;
    reader.system = "reader";
    reader.by_type.assign(ecs::type_id<ecs::Port<Gravity>>() + 1, ecs::AccessMask::none);
    reader.by_type[ecs::type_id<ecs::Port<Gravity>>()] = ecs::AccessMask::read;
    reader.used.assign(reader.by_type.size(), ecs::AccessMask::none);
    registry.set_access_mask(&reader);
    EXPECT_THROW((void)registry.resource<ecs::Port<Gravity>>(), ecs::UndeclaredAccess) << "declared read, it cannot be had to use";
    EXPECT_NE(registry.resource<const ecs::Port<Gravity>>(), nullptr);
    registry.set_access_mask(nullptr);
}

// Outside systems (set-up, tests, applying the command buffer) nothing is checked.
TEST(Schedule, AccessIsCheckedOnlyWhileASystemRuns) {
    ecs::Registry registry;
    const auto e = registry.create();
    registry.emplace<Position>(e);
    EXPECT_NO_THROW(registry.get<Position>(e).x = 1.0);
}

// Modules are ordered, not single systems: two modules' systems that write the same component in one
// phase run in the order the modules were installed, with no `after` between them; inside one module a
// conflict still needs one.
TEST(Schedule, ConflictsBetweenModulesFollowTheModulesOrder) {
    Fixture f;
    f.schedule.begin_module("hands");
    ASSERT_TRUE(f.schedule.add(make("grab", "input", {}, components<Points>())));
    f.schedule.end_module();
    f.schedule.begin_module("cutting");
    ASSERT_TRUE(f.schedule.add(make("cut", "input", {}, components<Points>())));
    f.schedule.end_module();
    ASSERT_TRUE(f.schedule.finalize());
    ASSERT_EQ(f.schedule.systems().size(), 2u);
    EXPECT_EQ(f.schedule.systems()[0].desc.name, "grab");
    EXPECT_EQ(f.schedule.systems()[1].desc.name, "cut");

    Fixture g;
    g.schedule.begin_module("hands");
    ASSERT_TRUE(g.schedule.add(make("grab", "input", {}, components<Points>())));
    ASSERT_TRUE(g.schedule.add(make("bend", "input", {}, components<Points>())));
    g.schedule.end_module();
    EXPECT_FALSE(g.schedule.finalize()) << "one module's own conflict is not settled for it";
}
