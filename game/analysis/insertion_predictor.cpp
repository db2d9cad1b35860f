#include "game/analysis/insertion_predictor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <sstream>

#include <glm/gtc/constants.hpp>

#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "engine/sched/clocks.hpp"
#include "game/experiment/insertion_experiment.hpp"
#include "game/species/species.hpp"
#include "game/world/world.hpp"

namespace ikebana::game {

using namespace components;

namespace {

// Only the covariates the species' extension terms read change the simulation, so only they are part
// of the key: a file of many rows with unknown columns still costs one simulation per condition.
std::string key_of(const InsertionConditions& c, const std::set<std::string>& used) {
    std::ostringstream k;
    k.precision(17);
    k << c.species << '|' << c.angle_deg << '|' << (c.depth_m ? *c.depth_m : -1.0) << '|' << c.insertion << '|'
      << (c.pins ? static_cast<long>(*c.pins) : -1L) << '|' << c.want_outcome;
    for (const auto& [name, v] : c.covariates.numeric) {
        if (used.contains(name)) k << '|' << name << '=' << v;
    }
    for (const auto& [name, v] : c.covariates.category) {
        if (used.contains(name)) k << '|' << name << '=' << v;
    }
    return k.str();
}

template <typename F>
void run_until(sched::DeterministicClock& clock, F&& done, double limit_s) {
    const std::int64_t end = clock.now_us() + static_cast<std::int64_t>(limit_s * 1e6);
    while (!done() && clock.now_us() < end) clock.run_for_us(10'000);
}

} // namespace

InsertionConditions conditions_for(const MeasuredTrial& t, const std::string& species_override, bool want_outcome) {
    InsertionConditions c;
    c.species = !species_override.empty() ? species_override : t.species.value_or("sunflower");
    c.angle_deg = t.angle_deg.value_or(45.0);
    if (t.depth_mm) c.depth_m = *t.depth_mm * 1e-3;
    c.insertion = t.insertion;
    c.pins = t.pins;
    c.want_outcome = want_outcome;
    return c;
}

InsertionConditions InsertionPredictor::conditions_of(const MeasuredData& data, std::size_t i, const std::string& species_override, bool want_outcome) {
    InsertionConditions c = conditions_for(data.trials[i], species_override, want_outcome);
    if (const auto* used = covariates_used(c.species, nullptr); used && !used->empty()) c.covariates = data.covariates_of(i, used);
    return c;
}

const std::set<std::string>* InsertionPredictor::covariates_used(const std::string& species, Error* error) {
    auto it = covariates_used_.find(species);
    if (it == covariates_used_.end()) {
        // A species that does not load is read once: conditions_of asks for every row first.
        if (const auto failed = failed_species_.find(species); failed != failed_species_.end()) {
            if (error) *error = failed->second;
            return nullptr;
        }
        auto def = load_species(species);
        if (!def) {
            failed_species_.emplace(species, def.error());
            if (error) *error = def.error();
            return nullptr;
        }
        std::set<std::string> used;
        // The terms on the holding read their columns too (they were left out: a hold term on a column the
        // row has was evaluated without it, and every row shared one simulation).
        for (const auto* terms : {&def->deterioration.terms, &def->deterioration.hold_terms}) {
            for (const auto& t : *terms) {
                used.insert(t.covariate);
                if (!t.times_covariate.empty()) used.insert(t.times_covariate); // an interaction reads it too
            }
        }
        it = covariates_used_.emplace(species, std::move(used)).first;
    }
    return &it->second;
}

std::string InsertionPredictor::key(const InsertionConditions& c) {
    const auto* used = covariates_used(c.species, nullptr);
    if (!used) return {};
    if (!shares_depth(c)) return key_of(c, *used);
    InsertionConditions deepest = c;
    deepest.depth_m.reset();
    deepest.pins.reset();
    return key_of(deepest, *used);
}

namespace {

// Rows the physics cannot mean: deeper than the pins are tall (the stem would be pushed through the
// base plate, and the force would keep rising), or more pins than lie under the stem's footprint.
Result<void> check_conditions(const InsertionConditions& c, const InsertionPredictor::Bench& b) {
    // (A row at exactly the pins' height is not refused for the last bit of 13 * 1e-3.)
    if (c.depth_m && *c.depth_m > b.pin_height_m + 1e-9) {
        char text[200];
        std::snprintf(text, sizeof text, "depth_mm: %.3g mm is deeper than the kenzan's pins are tall (%.3g mm); the stem would be pushed into the base plate",
                      *c.depth_m * 1e3, b.pin_height_m * 1e3);
        return make_error(ErrorCode::invalid_argument, text);
    }
    if (c.pins) {
        const double elevation = glm::radians(c.angle_deg);
        const double across = 2.0 * (b.radius_m + b.pin_radius_m);
        const double along = 2.0 * b.radius_m / std::sin(elevation) + b.pin_height_m / std::tan(elevation) + 2.0 * b.pin_radius_m;
        const auto most = static_cast<std::uint32_t>(std::ceil(across / b.pitch_m + 1.0) * std::ceil(along / b.pitch_m + 1.0));
        if (*c.pins > most) {
            char text[200];
            std::snprintf(text, sizeof text, "pins: %u is more than a %.3g mm stem at %.3g degrees can touch on this kenzan (at most %u)", *c.pins,
                          2e3 * b.radius_m, c.angle_deg, most);
            return make_error(ErrorCode::invalid_argument, text);
        }
    }
    return {};
}

// The placements that touched as many pins as the row says, or, when none did, those that came nearest
// (not all of them: a count the placements never reached still means more or fewer pins than average);
// their mean force and share that fell, the two states of the bottom mixed by their weights.
InsertionPrediction combine(const InsertionConditions& c, double broken_weight, const std::vector<PlacementResult> (&by_state)[2]) {
    InsertionPrediction out;
    out.broken_probability = broken_weight;
    for (const bool broken : {false, true}) {
        const double weight = broken ? broken_weight : 1.0 - broken_weight;
        const auto& placements = by_state[broken ? 1 : 0];
        if (weight <= 0.0 || placements.empty()) continue;
        std::vector<const PlacementResult*> matching;
        if (c.pins) {
            std::uint32_t nearest = std::numeric_limits<std::uint32_t>::max();
            for (const auto& p : placements) nearest = std::min(nearest, p.pins > *c.pins ? p.pins - *c.pins : *c.pins - p.pins);
            for (const auto& p : placements) {
                if ((p.pins > *c.pins ? p.pins - *c.pins : *c.pins - p.pins) == nearest) matching.push_back(&p);
            }
        } else {
            for (const auto& p : placements) matching.push_back(&p);
        }
        double force = 0.0;
        double fell = 0.0;
        for (const auto* p : matching) {
            force += p->force_n;
            fell += p->fell ? 1.0 : 0.0;
        }
        out.max_force_n += weight * force / static_cast<double>(matching.size());
        out.fall_probability += weight * fell / static_cast<double>(matching.size());
    }
    return out;
}

// A push to `stop_z_m` read off a push to the base plate. The hand moves the stem rigidly at a constant
// speed until it stops, so up to there the two pushes are the same simulation; the hand's last step is
// shortened to land on the stop exactly, which the samples (one a tick, 50 um apart) are interpolated
// to. What the stem does once let go (it settles for up to 10 ms before the row's push is read) is
// not in the samples: docs/benchmarks.md has how far the two differ.
PlacementResult at_stop(const std::vector<DepthSample>& samples, double stop_z_m) {
    PlacementResult p{};
    if (samples.empty()) return p;
    std::size_t j = 0;
    while (j < samples.size() && samples[j].lowest_z_m > stop_z_m) ++j;
    if (j == samples.size()) { // the push ended above the stop (the hand's force limit): as the row's would
        p.force_n = samples.back().max_force_n;
        p.pins = samples.back().max_pins;
        return p;
    }
    if (j == 0) {
        p.force_n = samples[0].max_force_n;
        p.pins = samples[0].max_pins;
        return p;
    }
    const auto& a = samples[j - 1];
    const auto& b = samples[j];
    const double span = a.lowest_z_m - b.lowest_z_m;
    const double t = span > 0.0 ? std::clamp((a.lowest_z_m - stop_z_m) / span, 0.0, 1.0) : 1.0;
    p.force_n = a.max_force_n + t * (b.max_force_n - a.max_force_n);
    p.pins = t > 0.5 ? b.max_pins : a.max_pins;
    return p;
}

} // namespace

Result<InsertionPredictor::Simulation> InsertionPredictor::simulate(const InsertionConditions& c, const std::set<std::string>& used, bool sample_depths) {
    // Only the covariates this species' terms read: the rest would make no difference.
    systems::insertion::Covariates environment;
    for (const auto& [name, v] : c.covariates.numeric) {
        if (used.contains(name)) environment.numeric[name] = v;
    }
    for (const auto& [name, v] : c.covariates.category) {
        if (used.contains(name)) environment.category[name] = v;
    }
    auto bench = make_bench_world(c.species, kenzan_, 1, std::move(environment));
    if (!bench) return std::move(bench).error();
    World& w = *bench->world;
    auto& r = w.sim;
    const ecs::Entity flower = bench->flower;
    const Kenzan& k = *r.single<Kenzan>();
    auto& model = r.get<PinResistance>(flower);
    // The split is conditioned on below, not drawn.
    const std::vector<double> hazards = model.break_probability_by_insertion;
    model.break_probability_by_insertion.clear();
    double sound = 1.0;
    for (std::uint32_t j = 1; j <= c.insertion && !hazards.empty(); ++j) sound *= 1.0 - hazards[std::min<std::size_t>(j, hazards.size()) - 1];

    Simulation sim;
    sim.broken_weight = hazards.empty() ? 0.0 : 1.0 - sound;
    const double radius = 0.5 * r.get<StemRestShape>(flower).diameter_m;
    const double pin_top = k.origin_m.z + k.pin_height_m();
    sim.bench = Bench{pin_top, k.pin_height_m(), k.pitch_m, 0.5 * k.pin.trunk_diameter_m, radius};
    if (auto ok = check_conditions(c, sim.bench); !ok) return std::move(ok).error();
    const double elevation = glm::radians(c.angle_deg);
    r.emplace<ScriptedInsertion>(flower);
    sched::DeterministicClock clock(w.schedule);
    clock.measure_durations(false); // nobody reads the insertion's timings

    const auto numeric = [&](const char* name) {
        const auto it = c.covariates.numeric.find(name);
        return used.contains(name) && it != c.covariates.numeric.end() ? it->second : 0.0;
    };
    const bool reuse = numeric("hole_reuse") > 0.5;
    const double minutes_since_cut = std::max(0.0, numeric("minutes_since_cut"));

    for (const bool broken : {false, true}) {
        const double weight = broken ? sim.broken_weight : 1.0 - sim.broken_weight;
        if (weight <= 0.0) continue;
        auto& placements = sim.placements[broken ? 1 : 0];
        auto& sampled = sim.samples[broken ? 1 : 0];
        for (int i = 0; i < 4; ++i) {
            for (int a = 0; a < 4; ++a) {
                auto& history = r.get<InsertionHistory>(flower);
                history.insertions = c.insertion - 1;
                history.insertions_total = c.insertion - 1;
                history.bottom_broken = broken;
                history.records.clear();
                history.holes.clear();
                const glm::dvec2 landing = k.pitch_m * glm::dvec2{(i + 0.5) / 4.0, ((3 * i) % 4 + 0.5) / 4.0};
                // The row's own state where the world would otherwise make it up: a re-used hole
                // is an earlier hole at this landing, and the cut happened that long ago.
                if (reuse) history.holes.push_back(glm::dvec2{k.origin_m.x + landing.x, k.origin_m.y + landing.y});
                history.cut_at_us = clock.now_us() - static_cast<std::int64_t>(minutes_since_cut * 60e6);
                const double azimuth = (a + 0.125) * 0.5 * glm::pi<double>();
                auto& hand = r.get<ScriptedInsertion>(flower);
                hand.axis = {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
                hand.bottom_m = {k.origin_m.x + landing.x, k.origin_m.y + landing.y, pin_top + 0.005 + radius * std::cos(elevation)};
                hand.speed_m_s = 0.05;
                hand.stop_z_m = c.depth_m && !sample_depths ? pin_top - *c.depth_m : k.origin_m.z;
                hand.max_push_n = 50.0;
                hand.stage = ScriptedInsertion::Stage::pushing;
                const auto pushing = [&] { return r.get<ScriptedInsertion>(flower).stage != ScriptedInsertion::Stage::released; };
                if (sample_depths) {
                    // A tick at a time, the stem's lowest point and what the insertion's record holds.
                    std::vector<DepthSample> samples;
                    const double lean = radius * std::sqrt(std::max(0.0, 1.0 - hand.axis.z * hand.axis.z));
                    const std::int64_t end = clock.now_us() + 5'000'000;
                    while (pushing() && clock.now_us() < end) {
                        clock.run_for_us(1000);
                        const auto& h = r.get<InsertionHistory>(flower);
                        DepthSample s{r.get<ScriptedInsertion>(flower).bottom_m.z - lean, 0.0, 0};
                        if (!h.records.empty()) {
                            s.max_force_n = h.records.back().max_resistance_n;
                            s.max_pins = h.records.back().max_pins;
                        }
                        samples.push_back(s);
                    }
                    sampled.push_back(std::move(samples));
                } else {
                    run_until(clock, [&] { return !pushing(); }, 5.0);
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
                }
                // Lift it clear for the next placement.
                auto& lift = r.get<ScriptedInsertion>(flower);
                lift.bottom_m.z = pin_top + 0.05;
                lift.stage = ScriptedInsertion::Stage::lifted;
                clock.run_for_us(2000);
            }
        }
    }
    return sim;
}

Result<InsertionPrediction> InsertionPredictor::predict(const InsertionConditions& c) {
    Error error{};
    const auto* used_set = covariates_used(c.species, &error);
    if (!used_set) return error;
    const std::set<std::string>& used = *used_set;
    const std::string key = key_of(c, used);
    if (const auto it = cache_.find(key); it != cache_.end()) return it->second;
    if (c.insertion < 1) return make_error(ErrorCode::invalid_argument, "insertion must be 1 or more");

    if (shares_depth(c)) {
        // Rows that differ only in depth (and pins) share one push to the base plate, read at each
        // row's depth: a file of continuous depths costs one simulation per condition, not per row.
        InsertionConditions deepest = c;
        deepest.depth_m.reset();
        deepest.pins.reset();
        const std::string profile_key = key_of(deepest, used);
        auto it = profiles_.find(profile_key);
        if (it == profiles_.end()) {
            auto sim = simulate(deepest, used, true);
            if (!sim) return std::move(sim).error();
            // Kept for the rows that share it, the oldest let go beyond max_profiles (about 0.3 MB
            // each: rows whose extension reads a continuous covariate share nothing).
            if (profile_order_.size() >= max_profiles_) {
                profiles_.erase(profile_order_.front());
                profile_order_.pop_front();
            }
            it = profiles_.emplace(profile_key, std::move(sim).value()).first;
            profile_order_.push_back(profile_key);
            ++simulated_;
        }
        const Simulation& profile = it->second;
        if (auto ok = check_conditions(c, profile.bench); !ok) return std::move(ok).error();
        std::vector<PlacementResult> by_state[2];
        for (std::size_t state = 0; state < 2; ++state) {
            for (const auto& samples : profile.samples[state]) by_state[state].push_back(at_stop(samples, profile.bench.pin_top_m - *c.depth_m));
        }
        const auto out = combine(c, profile.broken_weight, by_state);
        cache_.emplace(key, out);
        return out;
    }
    auto sim = simulate(c, used, false);
    if (!sim) return std::move(sim).error();
    const auto out = combine(c, sim->broken_weight, sim->placements);
    cache_.emplace(key, out);
    ++simulated_;
    return out;
}

std::vector<std::size_t> InsertionPredictor::simulation_order(const std::vector<InsertionConditions>& rows) {
    std::vector<std::string> keys;
    keys.reserve(rows.size());
    for (const auto& r : rows) keys.push_back(key(r));
    std::vector<std::size_t> order(rows.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
    return order;
}

} // namespace ikebana::game
