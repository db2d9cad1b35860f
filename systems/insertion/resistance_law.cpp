#include "systems/insertion/resistance_law.hpp"

namespace ikebana::systems::insertion {

double pin_resistance_n(const components::PinContact& p, const components::PinResistance& model, double soft_n_per_m) {
    if (model.kind == components::ResistanceKind::hard_eq6) {
        return model.pith_trunk_n_per_m * p.trunk_in_pith_m + model.cortex_trunk_n_per_m * (p.trunk_m - p.trunk_in_pith_m) +
               model.cortex_tip_n_per_m * (p.tip_m - p.tip_in_pith_m) + model.pith_tip_n_per_m * p.tip_in_pith_m;
    }
    return soft_n_per_m * (p.tip_m + p.trunk_m);
}

} // namespace ikebana::systems::insertion
