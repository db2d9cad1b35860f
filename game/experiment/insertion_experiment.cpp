#include "game/experiment/insertion_experiment.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <thread>
#include <mutex>
#include <atomic>
#include <exception>
#include <optional>

#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>

#include "engine/assets/json_checker.hpp"
#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/stem.hpp"
#include "engine/sched/clocks.hpp"
#include "game/kenzan/kenzan_layout.hpp"
#include "game/species/species.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"

namespace ikebana::game {

using namespace components;

namespace {

constexpr double gf = 9.80665e-3;

std::uint64_t mix(std::uint64_t a, std::uint64_t b) {
    std::uint64_t z = a * 0x9e3779b97f4a7c15ull + b + 0x632be59bd9b4e019ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Runs the clock in 10 ms steps until `done` or `limit_s` of simulated time.
template <typename F>
void run_until(sched::DeterministicClock& clock, F&& done, double limit_s) {
    const std::int64_t end = clock.now_us() + static_cast<std::int64_t>(limit_s * 1e6);
    while (!done() && clock.now_us() < end) clock.run_for_us(10'000);
}

} // namespace

Result<SceneDef> experiment_bench_scene(const std::string& species, const std::string& kenzan_layout, std::uint64_t seed,
                                        systems::insertion::Covariates environment) {
    auto kenzan = load_kenzan(kenzan_layout);
    if (!kenzan) return std::move(kenzan).error();
    SceneDef scene{};
    scene.seed = seed;
    scene.gravity_m_s2 = {0.0, 0.0, -9.80665};
    scene.table_height_m = 0.0;
    scene.kenzan_layout = kenzan_layout;
    scene.kenzan_position_m = {0.0, 0.0, kenzan->base_thickness_m};
    scene.environment = std::move(environment);
    scene.flowers.push_back({species, Placement::lying, {0.3, 0.0, 0.0}, {1.0, 0.0, 0.0}, 0.0});
    return scene;
}

Result<BenchWorld> make_bench_world(const std::string& species, const std::string& kenzan_layout, std::uint64_t seed,
                                    systems::insertion::Covariates environment) {
    auto scene = experiment_bench_scene(species, kenzan_layout, seed, std::move(environment));
    if (!scene) return std::move(scene).error();
    auto world = World::create(*scene, WorldOptions{.rate_overrides = {}, .force_scheme = {}, .main_lane_systems = {}, .frames = false});
    if (!world) return std::move(world).error();
    const ecs::Entity flower = (*world)->flowers[0].entity;
    return BenchWorld{std::move(world).value(), flower};
}

Result<TrialResult> run_insertion_trial(const ExperimentOptions& o, std::uint64_t trial_seed, bool stop_at_fall,
                                        std::optional<bool> force_broken) {
    auto bench = make_bench_world(o.species, o.kenzan, trial_seed, o.environment);
    if (!bench) return std::move(bench).error();
    World& w = *bench->world;
    auto& r = w.sim;
    const ecs::Entity flower = bench->flower;
    const Kenzan& k = *r.single<Kenzan>();
    if (force_broken.has_value()) {
        auto& model = r.get<PinResistance>(flower);
        model.break_probability_by_insertion.clear();
        r.get<InsertionHistory>(flower).bottom_broken = *force_broken;
    }
    const auto& rest = r.get<StemRestShape>(flower);
    const double radius = 0.5 * rest.diameter_m;
    const double pin_top = k.origin_m.z + k.pin_height_m();
    r.emplace<ScriptedInsertion>(flower);
    sched::DeterministicClock clock(w.schedule);
    clock.measure_durations(false); // nobody reads the trial's timings: 8 % of its time was the clock
    std::mt19937_64 hand_rng(mix(trial_seed, 0x51a7));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double elevation = glm::radians(o.angle_deg);

    TrialResult trial;
    for (std::uint32_t n = 1; n <= o.max_insertions; ++n) {
        if (std::find(o.cut_before.begin(), o.cut_before.end(), n) != o.cut_before.end()) {
            r.emplace_or_replace<CutRequest>(flower, o.cut_length_m);
            clock.run_for_us(1000);
        }
        // The experimenter picks the flower up, straightens it and aims somewhere near the centre.
        const glm::dvec2 landing = o.landing_m ? *o.landing_m : glm::dvec2{unit(hand_rng), unit(hand_rng)} * k.pitch_m;
        const double azimuth = o.azimuth_rad ? *o.azimuth_rad : unit(hand_rng) * 2.0 * glm::pi<double>();
        const glm::dvec3 axis{std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
        const double lowest_offset = radius * std::cos(elevation);
        auto& hand = r.get<ScriptedInsertion>(flower);
        hand.axis = axis;
        hand.bottom_m = {k.origin_m.x + landing.x, k.origin_m.y + landing.y, pin_top + 0.005 + lowest_offset};
        hand.speed_m_s = o.push_speed_m_s;
        hand.stop_z_m = o.depth_m > 0.0 ? pin_top - o.depth_m : k.origin_m.z;
        hand.max_push_n = 50.0;
        hand.lift_to_z_m = pin_top + 0.02 + lowest_offset;
        hand.stage = ScriptedInsertion::Stage::pushing;
        const bool broken_before = r.get<InsertionHistory>(flower).bottom_broken;
        run_until(clock, [&] { return r.get<ScriptedInsertion>(flower).stage == ScriptedInsertion::Stage::released; }, 5.0);
        const auto& engagement = r.get<PinEngagement>(flower);
        InsertionOutcome out{};
        out.number = n;
        out.pins = static_cast<std::uint32_t>(engagement.pins.size());
        out.depth_m = engagement.depth_m;
        out.holding_moment_nm = engagement.holding_moment_nm;
        out.gravity_moment_nm = engagement.gravity_moment_nm;
        run_until(clock, [&] { return r.get<KenzanGrip>(flower).fallen; }, o.settle_s);
        const auto& history = r.get<InsertionHistory>(flower);
        out.broken_before = broken_before;
        out.counted = history.insertions;
        if (!history.records.empty() && history.records.back().number == history.insertions) {
            const auto& record = history.records.back();
            out.broke = record.broke;
            out.max_pin_force_n = record.max_pin_force_n;
            out.max_resistance_n = record.max_resistance_n;
            out.pins_used = static_cast<std::uint32_t>(record.pins.size());
        }
        out.fell = r.get<KenzanGrip>(flower).fallen || !r.get<PinEngagement>(flower).in_kenzan;
        trial.insertions.push_back(out);
        if (out.broke && !trial.broke_at) trial.broke_at = n;
        if (out.fell && !trial.fell_at) trial.fell_at = n;
        if (out.fell && stop_at_fall) break;
        // Pull it out again (from wherever it stands or lies now).
        auto& pull = r.get<ScriptedInsertion>(flower);
        const auto& x = r.get<StemPoints>(flower).position_m;
        pull.axis = glm::normalize(x[1] - x[0]);
        pull.bottom_m = x[0];
        pull.stage = ScriptedInsertion::Stage::withdrawing;
        run_until(clock, [&] { return r.get<ScriptedInsertion>(flower).stage == ScriptedInsertion::Stage::lifted; }, 5.0);
    }
    trial.simulated_s = static_cast<double>(clock.now_us()) * 1e-6;
    return trial;
}

Result<ExperimentResult> run_insertion_experiment(const ExperimentOptions& o, const ExperimentProgress& progress) {
    ExperimentResult result;
    // An extended species may read columns this run does not set: said before the trials, with the
    // values used (an unreadable species is reported by the first trial's world, as before).
    if (auto species = load_species(o.species)) {
        result.species_id = species->id;
        result.missing_covariates = systems::insertion::missing_covariates(species->deterioration.terms, o.environment);
    }
    const auto start = std::chrono::steady_clock::now();
    // Trials are independent worlds, each seeded by its number: they run on every core, and are summed
    // in trial order afterwards, so any thread count gives the same result as one.
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    result.threads = static_cast<unsigned>(std::min<std::uint64_t>(o.threads > 0 ? o.threads : cores, std::max(1u, o.trials)));
    std::vector<std::optional<Result<TrialResult>>> runs(o.trials);
    std::atomic<std::uint32_t> next{0};
    std::atomic<bool> failed{false};
    std::mutex progress_mutex;
    std::uint32_t done = 0;
    if (progress) progress(0, o.trials);
    std::vector<std::exception_ptr> thrown(o.trials); // a trial's exception, rethrown here after the join
    auto work = [&] {
        for (std::uint32_t t = next++; t < o.trials && !failed; t = next++) {
            try {
                runs[t] = run_insertion_trial(o, mix(o.seed, t));
                if (!*runs[t]) failed = true; // the others stop at their next trial; the first error is reported
                const std::lock_guard lock(progress_mutex);
                ++done;
                if (progress && done < o.trials) progress(done, o.trials);
            } catch (...) {
                thrown[t] = std::current_exception();
                failed = true;
            }
        }
    };
    {
        std::vector<std::jthread> workers;
        for (unsigned i = 1; i < result.threads; ++i) workers.emplace_back(work);
        work();
    }
    // As one thread would end: at the earliest trial that failed, by an error or by an exception.
    for (std::uint32_t t = 0; t < o.trials; ++t) {
        if (thrown[t]) std::rethrow_exception(thrown[t]);
        if (runs[t] && !*runs[t]) break;
    }
    std::vector<double> force_sum;
    std::vector<std::uint32_t> force_count;
    for (std::uint32_t t = 0; t < o.trials; ++t) {
        if (!runs[t]) continue; // not run: a trial before it failed
        auto& trial = *runs[t];
        if (!trial) return std::move(trial).error();
        for (const auto& ins : trial->insertions) {
            if (force_sum.size() < ins.number) {
                force_sum.resize(ins.number, 0.0);
                force_count.resize(ins.number, 0);
            }
            force_sum[ins.number - 1] += ins.max_pin_force_n / gf;
            ++force_count[ins.number - 1];
            if (result.pins_histogram.size() <= ins.pins) result.pins_histogram.resize(ins.pins + 1, 0);
            ++result.pins_histogram[ins.pins];
        }
        result.mean_insertions_to_break += trial->broke_at.value_or(o.max_insertions + 1);
        result.mean_insertions_to_fall += trial->fell_at.value_or(o.max_insertions + 1);
        result.trials_never_broke += trial->broke_at ? 0 : 1;
        result.trials_never_fell += trial->fell_at ? 0 : 1;
        result.simulated_s += trial->simulated_s;
        result.trials.push_back(std::move(trial).value());
    }
    if (progress) progress(o.trials, o.trials);
    if (o.trials > 0) {
        result.mean_insertions_to_break /= o.trials;
        result.mean_insertions_to_fall /= o.trials;
    }
    for (std::size_t i = 0; i < force_sum.size(); ++i) result.force_by_insertion_gf.push_back(force_sum[i] / std::max(1u, force_count[i]));
    result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::string experiment_json(const ExperimentResult& r, const ExperimentOptions& o) {
    nlohmann::ordered_json j;
    j["trials"] = o.trials;
    j["seed"] = o.seed;
    j["angle_deg"] = o.angle_deg;
    j["species"] = o.species;
    j["mean_insertions_to_break"] = r.mean_insertions_to_break;
    j["mean_insertions_to_fall"] = r.mean_insertions_to_fall;
    j["trials_never_broke"] = r.trials_never_broke;
    j["trials_never_fell"] = r.trials_never_fell;
    j["paper"] = {{"break", 2.6}, {"fall", 5.8}, {"max_per_pin_gf", {121, 115, 103, 101, 98, 97}}};
    j["force_by_insertion_gf"] = r.force_by_insertion_gf;
    j["pins_engaged_histogram"] = r.pins_histogram;
    nlohmann::ordered_json missing = nlohmann::ordered_json::array();
    for (const auto& m : r.missing_covariates) {
        if (m.numeric) missing.push_back({{"covariate", m.name}, {"used", m.value}, {"fitted_range", {m.low, m.high}}});
        else missing.push_back({{"covariate", m.name}, {"used", "reference level"}});
    }
    j["missing_covariates"] = missing;
    nlohmann::ordered_json trials = nlohmann::ordered_json::array();
    for (const auto& t : r.trials) {
        trials.push_back({{"insertions_until_break", t.broke_at ? nlohmann::ordered_json(*t.broke_at) : nlohmann::ordered_json()},
                          {"insertions_until_fall", t.fell_at ? nlohmann::ordered_json(*t.fell_at) : nlohmann::ordered_json()}});
    }
    j["per_trial"] = trials;
    j["simulated_s"] = r.simulated_s;
    j["wall_s"] = r.wall_s;
    return assets::json_text(j, 2) + "\n";
}

std::string experiment_csv(const ExperimentResult& r) {
    std::ostringstream out;
    out << "trial,insertion,pins,depth_mm,max_pin_force_gf,max_resistance_gf,holding_mNm,gravity_mNm,broke,fell\n";
    for (std::size_t t = 0; t < r.trials.size(); ++t) {
        for (const auto& i : r.trials[t].insertions) {
            char line[256];
            std::snprintf(line, sizeof line, "%zu,%u,%u,%.3f,%.2f,%.2f,%.4f,%.4f,%d,%d\n", t + 1, i.number, i.pins, i.depth_m * 1e3,
                          i.max_pin_force_n / gf, i.max_resistance_n / gf, i.holding_moment_nm * 1e3, i.gravity_moment_nm * 1e3,
                          i.broke ? 1 : 0, i.fell ? 1 : 0);
            out << line;
        }
    }
    return out.str();
}

std::string experiment_report(const ExperimentResult& r, const ExperimentOptions& o) {
    std::ostringstream out;
    char line[256];
    out << "trial  insertions until break  insertions until fall\n";
    for (std::size_t t = 0; t < r.trials.size(); ++t) {
        const auto& tr = r.trials[t];
        std::snprintf(line, sizeof line, "%5zu  %22s  %21s\n", t + 1, tr.broke_at ? std::to_string(*tr.broke_at).c_str() : "never",
                      tr.fell_at ? std::to_string(*tr.fell_at).c_str() : "never");
        out << line;
    }
    std::snprintf(line, sizeof line, "\nmean insertions until the bottom breaks: %.2f   (paper: 2.6)\n", r.mean_insertions_to_break);
    out << line;
    std::snprintf(line, sizeof line, "mean insertions until the flower falls:  %.2f   (paper: 5.8)\n", r.mean_insertions_to_fall);
    out << line;
    if (r.trials_never_broke || r.trials_never_fell) {
        std::snprintf(line, sizeof line, "(trials that never broke: %u, never fell: %u, within %u insertions; counted as %u)\n",
                      r.trials_never_broke, r.trials_never_fell, o.max_insertions, o.max_insertions + 1);
        out << line;
    }
    const double paper[] = {121, 115, 103, 101, 98, 97};
    out << "\ninsertion  simulated max per pin [gf]  paper Table 2 [gf]\n";
    for (std::size_t i = 0; i < r.force_by_insertion_gf.size(); ++i) {
        std::snprintf(line, sizeof line, "%9zu  %26.1f  %18s\n", i + 1, r.force_by_insertion_gf[i],
                      i < 6 ? std::to_string(static_cast<int>(paper[i])).c_str() : "-");
        out << line;
    }
    out << "\npins engaged per insertion (the paper assumes 4):";
    std::uint32_t total = 0;
    for (auto c : r.pins_histogram) total += c;
    for (std::size_t p = 0; p < r.pins_histogram.size(); ++p) {
        if (r.pins_histogram[p] == 0) continue;
        std::snprintf(line, sizeof line, "  %zu pins: %.0f%%", p, 100.0 * r.pins_histogram[p] / std::max(1u, total));
        out << line;
    }
    for (const auto& m : r.missing_covariates) out << "\n\n" << missing_covariate_sentence(r.species_id, m);
    out << "\n";
    std::snprintf(line, sizeof line, "\n%.1f s simulated in %.2f s wall time (%.0fx real time, %u thread%s)\n", r.simulated_s, r.wall_s,
                  r.wall_s > 0 ? r.simulated_s / r.wall_s : 0.0, r.threads, r.threads == 1 ? "" : "s");
    out << line;
    return out.str();
}

} // namespace ikebana::game
