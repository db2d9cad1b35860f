#pragma once
// What a cut (C) and pruning (P) need at run time, reserved when the scene loads. Both change a stem's
// structure on the 1 kHz lane, which allocates nothing (glibc's allocator locks do not inherit
// priority): a cut works in the scratch here; a twig pruned off takes its kit (its list of twigs, its
// Cutting and look, made beforehand), a stripped leaf or blossom its stalk's kit (a short stem built
// upright at the origin, turned and moved to where it grows); the registry has room for the entities and
// components they add. Each kit is used once (a twig or part comes off once).
#include <cstddef>
#include <optional>
#include <vector>

#include "components/appearance.hpp"
#include "components/insertion.hpp"
#include "components/stem.hpp"
#include "engine/ecs/entity.hpp"
#include "engine/ecs/fwd.hpp"
#include "engine/ecs/hierarchy.hpp"

namespace ikebana::systems {

// Working memory for a cut, each at the size of the largest stem a species may have (201 points) and the
// most twigs one may carry (120).
struct CutScratch {
    std::vector<glm::dvec3> before, fresh;
    std::vector<double> arc, at, curvature, angle;
    std::vector<glm::dvec2> direction;
    std::vector<glm::dvec3> twig_moved;
    std::vector<std::uint8_t> twig_gone;
    std::vector<ecs::Entity> kept, gone;
};

struct LooseBranchKit {
    ecs::Entity twig;
    components::Twigs twigs; // room for every twig below it
    components::Cutting cutting;
    std::optional<components::FlowerLook> look;
    bool used = false;
};

// Stalk geometry: 10 mm, two segments, 1 mm across, 0.2 g (a leaf's stalk); built upright at the origin.
struct StalkKit {
    ecs::Entity part;
    components::StemPoints points;
    components::StemRestShape rest;
    components::StemSprings springs;
    components::StemFrame frame;
    components::StemLoads loads;
    components::Cutting cutting;
    std::optional<components::FlowerLook> look;
    ecs::Children children; // room for the part
    bool used = false;
};

struct StructureReserve {
    CutScratch cut;
    std::vector<LooseBranchKit> branches; // by twig entity
    std::vector<StalkKit> stalks;         // by part entity
    // What a twig or part's kit is; null when it has none (a flower added after the scene loaded).
    [[nodiscard]] LooseBranchKit* branch_for(ecs::Entity twig);
    [[nodiscard]] StalkKit* stalk_for(ecs::Entity part);
};

inline constexpr std::size_t most_stem_points = 256; // species: at most 200 segments
inline constexpr std::size_t most_twigs = 128;       // species: at most 120 twigs
inline constexpr double stalk_length_m = 0.01;

// Builds the reserve for every flower in `registry` (its twigs, its leaves and blossoms and theirs) and
// the registry's room for what pruning them adds; sets it as the registry's StructureReserve resource.
void reserve_structure_changes(ecs::Registry& registry);

} // namespace ikebana::systems
