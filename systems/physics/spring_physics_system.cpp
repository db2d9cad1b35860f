#include "systems/physics/spring_physics_system.hpp"

#include <algorithm>
#include <cmath>

#include "engine/ecs/registry.hpp"
#include "systems/physics/table_support_system.hpp"

namespace ikebana::systems {

void SpringPhysicsSystem::operator()(sched::SystemContext& ctx) {
    auto& registry = ctx.registry;
    const auto* settings = registry.resource<const components::PhysicsSettings>();
    const glm::dvec3 gravity = settings ? settings->gravity_m_s2 : components::PhysicsSettings{}.gravity_m_s2;
    if (const auto* capacity = registry.resource<const components::BodyCapacity>(); capacity && capacity != sized_for_) {
        size_for(*capacity, physics::tick_parts(ctx.dt_s));
    }
    stems_.clear();
    tree_roots_.clear();
    registry.view<components::StemPoints, const components::StemRestShape, const components::StemSprings, components::StemLoads>().each(
        [&](ecs::Entity e, components::StemPoints& points, const components::StemRestShape& rest,
            const components::StemSprings& springs, components::StemLoads& loads) {
            // A twig moves with its stem, a stem with twigs with them: one body (step_trees).
            if (registry.all_of<components::StemFork>(e)) return;
            if (const auto* twigs = registry.try_get<const components::Twigs>(e); twigs && !twigs->entities.empty()) {
                tree_roots_.push_back(e);
                return;
            }
            const auto* clamp = registry.try_get<const components::StemClamp>(e);
            const auto* frame = registry.try_get<const components::StemFrame>(e);
            // A tick longer than the paper's in equal parts (see tick_parts); external forces act
            // through all of them. The last part's end forces are what a hand feels.
            const std::size_t parts = physics::tick_parts(ctx.dt_s);
            const bool held = std::any_of(points.pinned.begin(), points.pinned.end(), [](std::uint8_t p) { return p != 0; });
            stems_.push_back({&points, &rest, &springs, clamp, frame, &loads, parts, held, true});
        });
    // The tick in rounds, one a part (tick_parts: one at the paper's rate); a round's stems are solved four
    // to a register (step_stems: each stem's results are what stepping it alone gives, whatever shares it).
    order_.resize(stems_.size());
    for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = i;
    // Longest first: a group of four costs its longest stem's rows, so similar lengths share a group,
    // and one left alone (solved without lanes) is a short one. Ties by index, the order stable_sort
    // gave, without its buffer: std::sort allocates nothing (nothing on the 1 kHz lane may).
    std::sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
        const std::size_t na = stems_[a].points->position_m.size();
        const std::size_t nb = stems_[b].points->position_m.size();
        return na != nb ? na > nb : a < b;
    });
    // A stem's scratch and rim crossings are the ones at its rank by length: the r-th longest stem is no
    // longer than the r-th longest the scene can have, which that scratch was sized for (size_for).
    rank_.resize(stems_.size());
    for (std::size_t r = 0; r < order_.size(); ++r) rank_[order_[r]] = r;
    if (scratches_.size() < stems_.size()) scratches_.resize(stems_.size());
    // Where each lies across a container's rim, from where it is at the tick's start.
    if (supports_.size() < stems_.size()) supports_.resize(stems_.size());
    const auto* container = registry.single<const components::Container>();
    for (std::size_t k = 0; k < stems_.size(); ++k) {
        auto& support = supports_[rank_[k]];
        support.clear();
        if (container) rim_supports(*container, stems_[k].points->position_m, 0.5 * stems_[k].rest->diameter_m, support);
    }
    std::size_t rounds = 0;
    for (const auto& stem : stems_) rounds = std::max(rounds, stem.parts);
    if (lane_scratch_.size() < rounds) lane_scratch_.resize(rounds);
    for (std::size_t round = 0; round < rounds; ++round) {
        batch_.clear();
        batch_stem_.clear();
        for (const std::size_t k : order_) {
            auto& stem = stems_[k];
            if (stem.parts <= round || !stem.finite) continue;
            auto& scratch = scratches_[rank_[k]];
            scratch.want_end_force = stem.held && round + 1 == stem.parts; // only a held stem's last part is felt
            batch_.push_back({stem.points, stem.rest, stem.springs, stem.clamp, &scratch, ctx.dt_s / static_cast<double>(stem.parts), stem.frame,
                              supports_[rank_[k]]});
            batch_stem_.push_back(k);
        }
        batch_ok_.assign(batch_.size(), 0);
        physics::step_stems(batch_, gravity, lane_scratch_[round], batch_ok_);
        for (std::size_t j = 0; j < batch_.size(); ++j) stems_[batch_stem_[j]].finite = batch_ok_[j] != 0;
    }
    for (std::size_t i = 0; i < stems_.size(); ++i) {
        auto& stem = stems_[i];
        auto& points = *stem.points;
        auto& loads = *stem.loads;
        const auto& end_force = scratches_[rank_[i]].end_force;
        if (stem.finite) {
            // The stem's own forces of this step (springs, hinges, clamp, gravity: without what other
            // systems pushed), for whatever else needs them (a hand that holds the stem): computed once
            // a tick, here.
            loads.force_n.resize(end_force.size());
            for (std::size_t p = 0; p < end_force.size(); ++p) loads.force_n[p] = end_force[p] - points.external_force_n[p];
        } else {
            // A non-finite step is refused: the stem stays where it was, at rest, rather than
            // carrying NaN into contacts and force output.
            ++failed_steps;
            for (auto& v : points.velocity_m_s) v = glm::dvec3{0.0};
            loads.force_n.assign(points.position_m.size(), glm::dvec3{0.0});
        }
        for (auto& f : points.external_force_n) f = glm::dvec3{0.0};
    }
    step_trees(ctx, gravity);
}

void SpringPhysicsSystem::size_for(const components::BodyCapacity& c, std::size_t rounds) {
    sized_for_ = &c;
    // By rank: the r-th longest stem's memory for the r-th longest the scene can have (stem_points is
    // longest first), a group of four for its first.
    const std::size_t stems = c.stem_points.size();
    for (auto* v : {&order_, &rank_, &batch_stem_}) v->reserve(stems);
    stems_.reserve(stems);
    batch_.reserve(stems);
    batch_ok_.reserve(stems);
    if (scratches_.size() < stems) scratches_.resize(stems);
    if (supports_.size() < stems) supports_.resize(stems);
    for (std::size_t r = 0; r < stems; ++r) {
        physics::reserve_scratch(scratches_[r], c.stem_points[r]);
        supports_[r].reserve(c.stem_points[r]);
    }
    // A round a part of the tick (one at the paper's 1 kHz; more when the haptic rate is set lower).
    if (lane_scratch_.size() < rounds) lane_scratch_.resize(rounds);
    for (auto& round : lane_scratch_) physics::reserve_scratch(round, c.stem_points);
    tree_roots_.reserve(c.trees);
    if (trees_.size() < c.trees) trees_.resize(c.trees);
    for (auto& chains : trees_) chains.reserve(c.tree_chains);
    if (tree_scratches_.size() < c.trees) tree_scratches_.resize(c.trees);
    for (auto& s : tree_scratches_) physics::reserve_scratch(s, c.tree_chains, c.tree_nodes, c.points);
    scratch_members_.reserve(c.tree_chains);
}

namespace {

struct Ground {
    const components::Table* table;
    const components::Container* container;
    const components::Kenzan* kenzan;
};

double ground_floor(const void* context, glm::dvec2 xy, double radius_m, double end_drop_m) {
    const auto* g = static_cast<const Ground*>(context);
    return support_floor_m(g->table, g->container, g->kenzan, xy, radius_m, end_drop_m);
}

glm::dvec3 ground_wall(const void* context, glm::dvec3 x, double radius_m) {
    const auto* g = static_cast<const Ground*>(context);
    return g->container ? wall_push_m(*g->container, x, radius_m) : glm::dvec3{0.0};
}

void ground_rim(const void* context, const std::vector<glm::dvec3>& x, double radius_m, std::vector<physics::SegmentSupport>& out) {
    const auto* g = static_cast<const Ground*>(context);
    out.clear();
    if (g->container) rim_supports(*g->container, x, radius_m, out);
}

} // namespace

void SpringPhysicsSystem::step_trees(sched::SystemContext& ctx, glm::dvec3 gravity) {
    using namespace components;
    auto& registry = ctx.registry;
    // What the branches rest on, in their solve (stem_tree.hpp: TreeSupport); table_support leaves their floors to it.
    const Ground ground{registry.resource<const Table>(), registry.single<const Container>(), registry.single<const Kenzan>()};
    physics::TreeSupport support;
    support.floor_m = ground.table || ground.container || ground.kenzan ? &ground_floor : nullptr;
    support.wall_push_m = ground.container ? &ground_wall : nullptr;
    support.rim_m = ground.container ? &ground_rim : nullptr;
    support.context = &ground;
    support.gravity_m_s2 = std::abs(gravity.z) > 0.0 ? std::abs(gravity.z) : support.gravity_m_s2;
    if (ground.table) support.friction = ground.table->friction;
    if (trees_.size() < tree_roots_.size()) trees_.resize(tree_roots_.size());
    if (tree_scratches_.size() < tree_roots_.size()) tree_scratches_.resize(tree_roots_.size());
    for (std::size_t t = 0; t < tree_roots_.size(); ++t) {
        const ecs::Entity root = tree_roots_[t];
        auto& chains = trees_[t];
        chains.clear();
        const auto chain_of = [&](ecs::Entity e, std::int32_t parent, const StemFork* fork) {
            chains.push_back({&registry.get<StemPoints>(e), &registry.get<const StemRestShape>(e), &registry.get<const StemSprings>(e),
                              parent < 0 ? registry.try_get<const StemClamp>(e) : nullptr, registry.try_get<const StemFrame>(e), parent, fork});
        };
        chain_of(root, -1, nullptr);
        std::vector<ecs::Entity>& members = scratch_members_;
        members.assign(1, root);
        bool whole = true;
        for (const ecs::Entity twig : registry.get<const Twigs>(root).entities) {
            const auto* fork = registry.try_get<const StemFork>(twig);
            if (!fork || !registry.all_of<StemPoints>(twig) || !registry.all_of<StemLoads>(twig)) {
                whole = false;
                break;
            }
            const auto parent = std::find(members.begin(), members.end(), fork->parent);
            if (parent == members.end()) { // listed before its parent: not a tree this system can solve
                whole = false;
                break;
            }
            chain_of(twig, static_cast<std::int32_t>(parent - members.begin()), fork);
            members.push_back(twig);
        }
        bool held = false;
        for (const auto& chain : chains) {
            held = held || std::any_of(chain.points->pinned.begin(), chain.points->pinned.end(), [](std::uint8_t p) { return p != 0; });
        }
        const std::size_t parts = physics::tick_parts(ctx.dt_s);
        bool finite = whole;
        for (std::size_t k = 0; finite && k < parts; ++k) {
            finite = physics::step_tree(chains, gravity, ctx.dt_s / static_cast<double>(parts), tree_scratches_[t], held && k + 1 == parts, &support);
        }
        const auto& scratch = tree_scratches_[t];
        for (std::size_t c = 0; c < chains.size(); ++c) {
            auto& points = *chains[c].points;
            auto& loads = registry.get<StemLoads>(members[c]);
            if (finite) {
                loads.force_n = scratch.load[c];
            } else {
                // As for a chain: a non-finite step is refused and the body stays where it was, at rest.
                for (auto& v : points.velocity_m_s) v = glm::dvec3{0.0};
                loads.force_n.assign(points.position_m.size(), glm::dvec3{0.0});
            }
            for (auto& f : points.external_force_n) f = glm::dvec3{0.0};
        }
        if (!finite) ++failed_steps;
        // The twigs' hold on their parents' frames (their sides are in them), for the frames' update
        // (stem_frame, after this): a free branch's frame turns with its twigs, not on its own.
        for (std::size_t c = 1; finite && c < chains.size(); ++c) {
            auto* frame = registry.try_get<StemFrame>(members[static_cast<std::size_t>(chains[c].parent)]);
            const std::uint32_t segment = chains[c].fork->at_point - 1;
            if (!frame || segment >= frame->external_twist_nm.size()) continue;
            frame->external_twist_nm[segment] -= scratch.frame_gradient_nm[c];
            frame->external_twist_stiffness_nm.resize(frame->external_twist_nm.size(), 0.0);
            frame->external_twist_stiffness_nm[segment] += scratch.frame_stiffness_nm[c];
        }
    }
}

} // namespace ikebana::systems
