#include "systems/insertion/insertion_tracking_system.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

#include "engine/ecs/registry.hpp"
#include "systems/insertion/pin_geometry.hpp"
#include "systems/insertion/random.hpp"

namespace ikebana::systems {

using namespace components;

void InsertionTrackingSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    const Kenzan* kenzan = r.single<const Kenzan>();
    RandomStream* random = r.single<RandomStream>();
    if (!kenzan) return;
    r.view<const StemPoints, const StemRestShape, const PinResistance, InsertionHistory, PinEngagement>().each(
        [&](ecs::Entity flower, const StemPoints& points, const StemRestShape& rest, const PinResistance& model, InsertionHistory& history,
            PinEngagement& engagement) {
            const auto& x = points.position_m;
            if (x.size() < 2) return;
            insertion::StemEnd end{};
            end.bottom_m = x[0];
            end.axis = glm::normalize(x[1] - x[0]);
            end.radius_m = 0.5 * rest.diameter_m;
            end.pith_radius_m = model.kind == ResistanceKind::hard_eq6 ? 0.5 * model.pith_diameter_m : 0.0;
            end.length_m = std::max(3.0 * kenzan->pin_height_m(), 0.05);
            const bool was_in = engagement.in_kenzan;
            // Being in the pins is a matter of the stem's shape; a split bottom only grips less (the
            // pins in its first `seat_loss` hold nothing), it is no less in the kenzan.
            insertion::engaged_pins(end, *kenzan, engagement.pins);
            engagement.in_kenzan = !engagement.pins.empty();
            if (history.bottom_broken && model.broken_seat_loss_m > 0.0 && engagement.in_kenzan) {
                end.seat_loss_m = model.broken_seat_loss_m;
                insertion::engaged_pins(end, *kenzan, engagement.pins);
            }
            insertion::assign_lever_arms(end, *kenzan, engagement.pins);
            const double lowest = x[0].z - end.radius_m * std::sqrt(std::max(0.0, 1.0 - end.axis.z * end.axis.z));
            engagement.depth_m = engagement.in_kenzan ? kenzan->origin_m.z + kenzan->pin_height_m() - lowest : 0.0;
            if (!engagement.in_kenzan) {
                const double above_tips_m = lowest - (kenzan->origin_m.z + kenzan->pin_height_m());
                if (was_in) {
                    history.left_pins = true;
                    history.left_pins_us = ctx.time_us;
                    history.out_rise_m = above_tips_m;
                    history.left_at_m = glm::dvec2(x[0]);
                }
                history.out_rise_m = std::max(history.out_rise_m, above_tips_m);
                return;
            }
            const std::int64_t out_us = ctx.time_us - history.left_pins_us;
            // Out long enough, and clear of the pins: risen over the tips, gone for half a second, or back
            // somewhere else (an end slid off the kenzan's side below the tips and put in elsewhere).
            const bool moved = glm::length(glm::dvec2(x[0]) - history.left_at_m) >= min_move_out_m;
            const bool really_out = out_us >= min_time_out_us && (history.out_rise_m >= min_rise_out_m || out_us >= min_time_hovering_us || moved);
            if (!was_in && (!history.left_pins || really_out)) {
                history.entry_counted = false; // really out and back: a new entry (a quick return is the same one)
                history.entry_held = false;
            }
            if (history.entry_counted) return;
            // Only a stem a hand put into the pins is an insertion (not one falling onto them): held at some
            // moment of this entry. One let go with its end just in, which its weight then takes deeper,
            // counts when it is pierced (a trainee's cherry once stood with "insertions 0").
            if (const auto* grasp = r.try_get<const Grasp>(flower); grasp && grasp->hands > 0) history.entry_held = true;
            if (engagement.depth_m < pierced_depth_m) return;
            history.entry_counted = true;
            if (!history.entry_held) return;

            // A new insertion of this stem end.
            InsertionRecord record{};
            record.number = ++history.insertions;
            ++history.insertions_total;
            record.start_us = ctx.time_us;
            record.angle_deg = glm::degrees(std::asin(std::clamp(end.axis.z, -1.0, 1.0)));
            const glm::dvec2 hole{x[0].x, x[0].y};
            for (const auto& h : history.holes) record.reused_hole = record.reused_hole || glm::length(h - hole) < end.radius_m;
            history.holes.push_back(hole);
            if (!history.bottom_broken && random && !model.break_probability_by_insertion.empty()) {
                const auto& p = model.break_probability_by_insertion;
                const double chance = p[std::min<std::size_t>(record.number, p.size()) - 1];
                if (insertion::next_unit(*random) < chance) {
                    history.bottom_broken = true;
                    record.broke = true;
                }
            }
            history.records.push_back(record);
        });
}

} // namespace ikebana::systems
