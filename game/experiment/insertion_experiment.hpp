#pragma once
// The paper's experiment (section 3.1), run through the live systems: a sunflower inserted into the
// kenzan at 45 degrees again and again until it falls, noting the insertion at which its bottom breaks
// and the one after which it falls; repeated per trial. Each insertion lands at a random place on the
// pin grid and leans in a random direction (the experimenter does not aim at a pin), which decides how
// many pins enter the stem.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include <glm/glm.hpp>

#include "game/scene/scene.hpp"
#include "game/species/species.hpp"
#include "game/world/world.hpp"
#include "systems/insertion/deterioration.hpp"

namespace ikebana::game {

struct ExperimentOptions {
    std::uint32_t trials = 15;
    std::uint64_t seed = 1;
    double angle_deg = 45.0;
    std::string species = "sunflower";
    std::string kenzan = "standard";
    std::uint32_t max_insertions = 15;
    double push_speed_m_s = 0.05;
    double settle_s = 2.0;
    // How far below the pin tips the stem's lowest point is pushed; <= 0: down to the base plate.
    double depth_m = 0.0;
    // Fixed landing for tests: offset from the kenzan centre and lean azimuth; random when empty.
    std::optional<glm::dvec2> landing_m;
    std::optional<double> azimuth_rad;
    // The experimenter cuts `cut_length_m` off the end before these insertions (1-based).
    std::vector<std::uint32_t> cut_before;
    double cut_length_m = 0.01;
    // Covariates an extended species may read that the world does not have (--env).
    systems::insertion::Covariates environment;
    // Trials run side by side on this many threads; 0: one per core. The result does not depend on it.
    unsigned threads = 0;
};

struct InsertionOutcome {
    std::uint32_t number;
    std::uint32_t pins;
    double depth_m;
    double max_pin_force_n;
    double max_resistance_n;
    double holding_moment_nm;
    double gravity_moment_nm;
    bool broke;
    bool fell;
    bool broken_before; // the bottom was already split when this insertion began
    std::uint32_t counted; // the flower's own insertion count after this insertion
    std::uint32_t pins_used; // distinct pins that were in the stem during the insertion (its history)
};

struct TrialResult {
    std::vector<InsertionOutcome> insertions;
    std::optional<std::uint32_t> broke_at;
    std::optional<std::uint32_t> fell_at;
    double simulated_s = 0.0;
};

struct ExperimentResult {
    std::vector<TrialResult> trials;
    double simulated_s = 0.0;
    double wall_s = 0.0;
    unsigned threads = 1; // the trials ran on
    // Means over trials; a trial that never broke (fell) within max_insertions counts as max + 1.
    double mean_insertions_to_break = 0.0;
    double mean_insertions_to_fall = 0.0;
    std::uint32_t trials_never_broke = 0;
    std::uint32_t trials_never_fell = 0;
    std::vector<double> force_by_insertion_gf;      // mean over trials of the largest single-pin force
    std::vector<std::uint32_t> pins_histogram;      // pins engaged at full depth, over all insertions
    // Columns the species' fitted extension reads that this run's environment does not set, and the
    // value each was taken at (systems/insertion/deterioration.hpp).
    std::vector<systems::insertion::MissingCovariate> missing_covariates;
    std::string species_id;
};

// Trials finished so far, of how many. Called from the threads that run them, one call at a time.
using ExperimentProgress = std::function<void(std::uint32_t done, std::uint32_t of)>;

// The experiment's bench: a kenzan of `kenzan_layout` standing on the table at the origin, and one
// flower of `species` lying 30 cm beside it for the scripted hand to pick up. The trials and the
// predictor of measured data both simulate insertions on it.
Result<SceneDef> experiment_bench_scene(const std::string& species, const std::string& kenzan_layout, std::uint64_t seed,
                                        systems::insertion::Covariates environment);

// That bench as a world (no hands, no frames: nothing is shown), with its one flower.
struct BenchWorld {
    std::unique_ptr<World> world;
    ecs::Entity flower;
};
Result<BenchWorld> make_bench_world(const std::string& species, const std::string& kenzan_layout, std::uint64_t seed,
                                    systems::insertion::Covariates environment);

Result<ExperimentResult> run_insertion_experiment(const ExperimentOptions& options, const ExperimentProgress& progress = {});

// One trial with a given number of insertions forced (it does not stop at a fall), for tests of
// Figure 12: returns the outcome of each insertion.
Result<TrialResult> run_insertion_trial(const ExperimentOptions& options, std::uint64_t trial_seed, bool stop_at_fall = true,
                                        std::optional<bool> force_broken_after = std::nullopt);

std::string experiment_json(const ExperimentResult& result, const ExperimentOptions& options);
std::string experiment_csv(const ExperimentResult& result);
std::string experiment_report(const ExperimentResult& result, const ExperimentOptions& options);

} // namespace ikebana::game
