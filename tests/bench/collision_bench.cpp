// A collision pass (collider update + detection) over an arrangement, with and without 1 000 extra
// Inactive parts. The paper's Inactive tag exists so that such parts cost nothing; the two figures
// should be the same within noise. Run: build/release/tests/bench/collision_bench
#include <benchmark/benchmark.h>

#include "components/collision.hpp"
#include "components/hand.hpp"
#include "components/flower.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/collision/collider_update_system.hpp"
#include "systems/collision/collision_detection_system.hpp"
#include "systems/physics/stem_builder.hpp"

using namespace ikebana;
using namespace ikebana::components;

namespace {
void build_arrangement(ecs::Registry& r, int inactive_parts) {
    const auto kenzan = r.create();
    r.emplace<Kenzan>(kenzan, Kenzan{"bench", {0, 0, 0}, 0.004, 20, 20, {0.0009, 0.011, 0.0015}, 0.008, 0.0});
    r.emplace<PassiveCollider>(kenzan);
    int placed = 0;
    for (int f = 0; f < 10; ++f) {
        systems::physics::StemSpec spec;
        spec.segments = 30;
        spec.base_m = {0.006 * (f % 5) - 0.012, 0.008 * (f / 5) - 0.004, 0.004};
        spec.direction = glm::normalize(glm::dvec3{0.1 * (f - 5), 0.05 * f, 1.0});
        auto stem = systems::physics::build_stem(spec);
        const auto flower = r.create();
        r.emplace<Flower>(flower, std::string("bench"), 0.05);
        r.emplace<StemPoints>(flower, stem.points);
        for (std::uint32_t i = 0; i < spec.segments; ++i) {
            const auto part = r.create();
            r.emplace<Part>(part, PartKind::stem, i, glm::dvec3{0.0}, std::string{});
            r.emplace<Collider>(part, ShapeKind::capsule, glm::dvec3{0.0}, glm::dvec3{0.0}, 0.00375, glm::dvec3{0.0});
            if (i == 0) r.emplace<ActiveCollider>(part);
            else r.emplace<PassiveCollider>(part);
            ecs::attach(r, part, flower);
        }
        for (int p = 0; p < inactive_parts / 10 && placed < inactive_parts; ++p, ++placed) {
            const auto petal = r.create();
            r.emplace<Part>(petal, PartKind::petal, spec.segments, glm::dvec3{0.01, 0.0, 0.0}, std::string{});
            r.emplace<Collider>(petal, ShapeKind::sphere, glm::dvec3{0.0}, glm::dvec3{0.0}, 0.01, glm::dvec3{0.0});
            r.emplace<InactiveCollider>(petal);
            ecs::attach(r, petal, flower);
        }
    }
    for (int h = 0; h < 2; ++h) {
        const auto hand = r.create();
        r.emplace<HandCube>(hand, static_cast<std::uint8_t>(h), 0.02);
        const glm::dvec3 at{h ? 0.05 : -0.05, 0.0, 0.15};
        r.emplace<Collider>(hand, ShapeKind::box, at, at, 0.0, glm::dvec3{0.01});
        r.emplace<ActiveCollider>(hand);
    }
}
} // namespace

static void BM_CollisionPass(benchmark::State& state) {
    ecs::Registry r;
    build_arrangement(r, static_cast<int>(state.range(0)));
    systems::ColliderUpdateSystem update;
    systems::CollisionDetectionSystem detect;
    sched::SystemContext ctx{r, 0, 1.0 / 16.0, 0};
    for (auto _ : state) {
        update(ctx);
        detect(ctx);
        benchmark::DoNotOptimize(r.resource<Contacts>()->list.size());
    }
    state.counters["contacts"] = static_cast<double>(r.resource<Contacts>()->list.size());
    state.counters["pairs_tested"] = static_cast<double>(r.resource<Contacts>()->pairs_tested);
    state.SetLabel(std::to_string(state.range(0)) + " inactive parts");
}
BENCHMARK(BM_CollisionPass)->Arg(0)->Arg(1000)->Repetitions(5)->ReportAggregatesOnly(true);

BENCHMARK_MAIN();
