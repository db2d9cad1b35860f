#include "systems/insertion/insertion_resistance_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "components/kenzan.hpp"
#include "engine/ecs/registry.hpp"
#include "systems/insertion/deterioration.hpp"
#include "systems/insertion/pin_geometry.hpp"
#include "systems/insertion/resistance_law.hpp"

namespace ikebana::systems {

using namespace components;

namespace {
// Made before the lane starts: a key longer than a string's small buffer would allocate to look up.
const std::string minutes_since_cut_key = "minutes_since_cut";
const std::string angle_key = "angle_deg";
const std::string hole_reuse_key = "hole_reuse";
const std::string pins_key = "pins";

template <typename Map, typename Value>
void set(Map& map, const std::string& key, const Value& value) {
    if (const auto it = map.find(key); it != map.end()) {
        it->second = value;
    } else {
        map.emplace(key, value); // the first time only
    }
}
} // namespace

void InsertionResistanceSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    const Kenzan* kenzan = r.single<const Kenzan>();
    const auto* settings = r.resource<const PhysicsSettings>();
    const double g = settings ? glm::length(settings->gravity_m_s2) : 9.80665;
    const auto* world_covariates = r.resource<const insertion::Covariates>();
    insertion::Covariates& covariates = covariates_;
    r.view<const StemPoints, const StemRestShape, const PinResistance, InsertionHistory, PinEngagement>().each(
        [&](ecs::Entity, const StemPoints& points, const StemRestShape& rest, const PinResistance& model, InsertionHistory& history,
            PinEngagement& engagement) {
            engagement.resistance_n = 0.0;
            engagement.holding_moment_nm = 0.0;
            engagement.gravity_moment_nm = 0.0;
            if (!engagement.in_kenzan || !kenzan) return;
            // Covariates a fitted extension may use: the world's, plus this insertion's own. Only a species
            // with an extension reads them (building the map was eight allocations a flower a tick).
            if (!model.extension.empty() || !model.hold_extension.empty()) {
                if (world_covariates) {
                    for (const auto& [key, value] : world_covariates->numeric) set(covariates.numeric, key, value);
                    for (const auto& [key, value] : world_covariates->category) set(covariates.category, key, value);
                }
                set(covariates.numeric, minutes_since_cut_key, static_cast<double>(ctx.time_us - history.cut_at_us) / 60e6);
                const bool recorded = !history.records.empty();
                set(covariates.numeric, angle_key, recorded ? history.records.back().angle_deg : std::numeric_limits<double>::quiet_NaN());
                set(covariates.numeric, hole_reuse_key, recorded ? (history.records.back().reused_hole ? 1.0 : 0.0) : std::numeric_limits<double>::quiet_NaN());
                set(covariates.numeric, pins_key, static_cast<double>(engagement.pins.size()));
            }
            const double soft = model.kind == ResistanceKind::soft_table
                                    ? insertion::soft_resistance_n_per_m(model, std::max(history.insertions, 1u), covariates)
                                    : 0.0;
            // A fitted extension multiplies a hard branch's Eq. 6 as well (the soft table has it already).
            const double extension = model.kind == ResistanceKind::soft_table
                                         ? 1.0
                                         : insertion::extension_factor(model.extension, std::max(history.insertions, 1u), covariates);
            const double broken = history.bottom_broken ? model.broken_holding_factor : 1.0;
            const double factor = broken * extension;
            // An extension that applies to the push alone leaves the holding moment the base model's.
            const bool hold_apart = !model.extension.empty() && model.extension_push_only;
            const double soft_base = hold_apart && model.kind == ResistanceKind::soft_table
                                         ? insertion::soft_resistance_n_per_m(model, std::max(history.insertions, 1u), covariates, false)
                                         : soft;
            // Terms on the holding alone move when it falls and leave the push as it is.
            const double hold = model.hold_extension.empty() ? 1.0 : insertion::extension_factor(model.hold_extension, std::max(history.insertions, 1u), covariates);
            for (auto& p : engagement.pins) {
                p.force_n = factor * insertion::pin_resistance_n(p, model, soft);
                engagement.resistance_n += p.force_n;
                const double holding_n = hold * (hold_apart ? broken * insertion::pin_resistance_n(p, model, soft_base) : p.force_n);
                engagement.holding_moment_nm += holding_n * p.lever_m;
            }
            // Gravity moment about the tipping edge, from the live mass points.
            const auto& x = points.position_m;
            const glm::dvec3 axis = glm::normalize(x[1] - x[0]);
            insertion::StemEnd end{x[0], axis, 0.5 * rest.diameter_m, 0.0, 0.0, 0.05};
            std::vector<PinContact> none;
            const glm::dvec3 edge = insertion::assign_lever_arms(end, *kenzan, none);
            const glm::dvec2 lean{insertion::lean_direction(axis)};
            double moment = 0.0;
            for (std::size_t i = 0; i < x.size(); ++i) moment += points.mass_kg[i] * g * glm::dot(glm::dvec2(x[i]) - glm::dvec2(edge), lean);
            engagement.gravity_moment_nm = std::max(0.0, moment);
            // Records keep the largest values seen during the insertion (what a sclerometer reads).
            if (!history.records.empty()) {
                auto& rec = history.records.back();
                rec.max_depth_m = std::max(rec.max_depth_m, engagement.depth_m);
                rec.max_resistance_n = std::max(rec.max_resistance_n, engagement.resistance_n);
                rec.max_pins = std::max(rec.max_pins, static_cast<std::uint32_t>(engagement.pins.size()));
                for (const auto& p : engagement.pins) {
                    rec.max_pin_force_n = std::max(rec.max_pin_force_n, p.force_n);
                    rec.pins.add(p.pin);
                }
            }
        });
}

} // namespace ikebana::systems
