#pragma once
// One pin's resistance. Hard branch: Eq. 6 with Table 1,
//   F = 7 d_p + 316 (d_c1 + d_c2) + 711 d_t1 + 40 d_t2   [gf, lengths in mm]
// i.e. per metre of pin: trunk in pith, trunk in cortex (either side), tip in cortex, tip in pith.
// Soft branch: the species' resistance per metre for this insertion times the pin's length inside.
#include "components/insertion.hpp"

namespace ikebana::systems::insertion {

[[nodiscard]] double pin_resistance_n(const components::PinContact& pin, const components::PinResistance& model,
                                      double soft_n_per_m);

} // namespace ikebana::systems::insertion
