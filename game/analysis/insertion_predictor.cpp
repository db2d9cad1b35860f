#include "game/analysis/insertion_predictor.hpp"

#include <cmath>
#include <sstream>

#include <glm/gtc/constants.hpp>

#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "engine/sched/clocks.hpp"
#include "game/kenzan/kenzan_layout.hpp"
#include "game/world/world.hpp"

namespace ikebana::game {

using namespace components;

namespace {

std::string key_of(const InsertionConditions& c) {
    std::ostringstream k;
    k.precision(17);
    k << c.species << '|' << c.angle_deg << '|' << (c.depth_m ? *c.depth_m : -1.0) << '|' << c.insertion << '|'
      << (c.pins ? static_cast<long>(*c.pins) : -1L) << '|' << c.want_outcome;
    for (const auto& [name, v] : c.covariates.numeric) k << '|' << name << '=' << v;
    for (const auto& [name, v] : c.covariates.category) k << '|' << name << '=' << v;
    return k.str();
}

struct PlacementResult {
    double force_n;
    std::uint32_t pins;
    bool fell;
};

template <typename F>
void run_until(sched::DeterministicClock& clock, F&& done, double limit_s) {
    const std::int64_t end = clock.now_us() + static_cast<std::int64_t>(limit_s * 1e6);
    while (!done() && clock.now_us() < end) clock.run_for_us(10'000);
}

} // namespace

Result<InsertionPrediction> InsertionPredictor::predict(const InsertionConditions& c) {
    const std::string key = key_of(c);
    if (const auto it = cache_.find(key); it != cache_.end()) return it->second;
    if (c.insertion < 1) return make_error(ErrorCode::invalid_argument, "insertion must be 1 or more");

    auto kenzan_def = load_kenzan(kenzan_);
    if (!kenzan_def) return std::move(kenzan_def).error();
    SceneDef scene{};
    scene.seed = 1;
    scene.gravity_m_s2 = {0.0, 0.0, -9.80665};
    scene.kenzan_layout = kenzan_;
    scene.kenzan_position_m = {0.0, 0.0, kenzan_def->base_thickness_m};
    scene.environment = c.covariates;
    scene.flowers.push_back({c.species, game::Placement::lying, {0.3, 0.0, 0.0}, {1.0, 0.0, 0.0}, 0.0});
    auto world = World::create(scene);
    if (!world) return std::move(world).error();
    World& w = **world;
    auto& r = w.sim;
    const ecs::Entity flower = w.flowers[0].entity;
    const Kenzan& k = *r.single<Kenzan>();
    auto& model = r.get<PinResistance>(flower);
    // The split is conditioned on below, not drawn.
    const std::vector<double> hazards = model.break_probability_by_insertion;
    model.break_probability_by_insertion.clear();
    double sound = 1.0;
    for (std::uint32_t j = 1; j <= c.insertion && !hazards.empty(); ++j) sound *= 1.0 - hazards[std::min<std::size_t>(j, hazards.size()) - 1];
    const double broken_weight = hazards.empty() ? 0.0 : 1.0 - sound;

    const double radius = 0.5 * r.get<StemRestShape>(flower).diameter_m;
    const double pin_top = k.origin_m.z + k.pin_height_m();
    const double elevation = glm::radians(c.angle_deg);
    r.emplace<ScriptedInsertion>(flower);
    sched::DeterministicClock clock(w.schedule);

    InsertionPrediction out;
    out.broken_probability = broken_weight;
    for (const bool broken : {false, true}) {
        const double weight = broken ? broken_weight : 1.0 - broken_weight;
        if (weight <= 0.0) continue;
        std::vector<PlacementResult> placements;
        for (int i = 0; i < 4; ++i) {
            for (int a = 0; a < 4; ++a) {
                auto& history = r.get<InsertionHistory>(flower);
                history.insertions = c.insertion - 1;
                history.insertions_total = c.insertion - 1;
                history.bottom_broken = broken;
                history.records.clear();
                history.holes.clear();
                const glm::dvec2 landing = k.pitch_m * glm::dvec2{(i + 0.5) / 4.0, ((3 * i) % 4 + 0.5) / 4.0};
                const double azimuth = (a + 0.125) * 0.5 * glm::pi<double>();
                auto& hand = r.get<ScriptedInsertion>(flower);
                hand.axis = {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
                hand.bottom_m = {k.origin_m.x + landing.x, k.origin_m.y + landing.y, pin_top + 0.005 + radius * std::cos(elevation)};
                hand.speed_m_s = 0.05;
                hand.stop_z_m = c.depth_m ? pin_top - *c.depth_m : k.origin_m.z;
                hand.max_push_n = 50.0;
                hand.stage = ScriptedInsertion::Stage::pushing;
                run_until(clock, [&] { return r.get<ScriptedInsertion>(flower).stage == ScriptedInsertion::Stage::released; }, 5.0);
                PlacementResult p{};
                const auto& h = r.get<InsertionHistory>(flower);
                if (!h.records.empty()) {
                    p.force_n = h.records.back().max_resistance_n;
                    p.pins = h.records.back().max_pins;
                }
                if (c.want_outcome) {
                    run_until(clock, [&] { return r.get<KenzanGrip>(flower).fallen; }, 2.0);
                    p.fell = r.get<KenzanGrip>(flower).fallen;
                }
                placements.push_back(p);
                // Lift it clear for the next placement.
                auto& lift = r.get<ScriptedInsertion>(flower);
                lift.bottom_m.z = pin_top + 0.05;
                lift.stage = ScriptedInsertion::Stage::lifted;
                clock.run_for_us(2000);
            }
        }
        std::vector<const PlacementResult*> used;
        for (const auto& p : placements) {
            if (!c.pins || p.pins == *c.pins) used.push_back(&p);
        }
        if (used.empty()) {
            for (const auto& p : placements) used.push_back(&p);
        }
        double force = 0.0;
        double fell = 0.0;
        for (const auto* p : used) {
            force += p->force_n;
            fell += p->fell ? 1.0 : 0.0;
        }
        out.max_force_n += weight * force / static_cast<double>(used.size());
        out.fall_probability += weight * fell / static_cast<double>(used.size());
    }
    cache_.emplace(key, out);
    return out;
}

} // namespace ikebana::game
