#pragma once
// The pins' resistance (sections 2.5 and 3.1) and what it holds (Eq. 7), in SI:
//  - each engaged pin resists with force f_i: hard branch, Eq. 6 with Table 1 (per metre of pin in
//    cortex or pith, cone tip or trunk); soft branch, the species' per-metre resistance for this
//    insertion count (Table 2 through the deterioration model) times the pin's length in the stem;
//    a split bottom holds `broken_holding_factor` of that;
//  - the sum resists insertion and withdrawal (what a hand pushing or pulling the stem feels);
//  - holding moment M_h = sum f_i * lever_i about the tipping edge (virtual work: tipping by d phi
//    pulls pin i out of the stem by lever_i * d phi) against the gravity moment m g r cos(theta),
//    taken live from the stem's mass points. The paper's Eq. 7 compares gf with gf*mm; here both
//    sides are moments in N*m.
#include <string_view>

#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "components/stem.hpp"
#include "engine/sched/system.hpp"
#include "systems/insertion/deterioration.hpp"

namespace ikebana::systems {

struct InsertionResistanceSystem {
    static constexpr std::string_view name = "insertion_resistance";
    static constexpr std::string_view lane = "sim";
    static constexpr std::string_view phase = "insertion";
    static constexpr std::string_view rate = "haptic";
    using reads = sched::Components<components::StemPoints, components::StemRestShape, components::PinResistance,
                                    components::PhysicsSettings, components::Kenzan, insertion::Covariates>;
    // InsertionHistory: the records keep each insertion's maxima.
    using writes = sched::Components<components::PinEngagement, components::InsertionHistory>;

    void operator()(sched::SystemContext& ctx);

private:
    // Kept from tick to tick: the map's nodes are made the first time each key is set and then only
    // written (building it anew was allocations a flower a tick on the 1 kHz lane). A covariate this
    // insertion does not have is NaN (numeric) or empty (category): absent, as extension_factor reads it.
    insertion::Covariates covariates_;
};

} // namespace ikebana::systems
