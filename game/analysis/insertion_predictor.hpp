#pragma once
// What the simulation predicts for one measured insertion, through the live systems: a headless world
// with the species and the kenzan, the flower's history set to the row's insertion count, and a
// scripted hand pushing it in at the row's angle and depth. Where the stem lands on the grid and
// whether its bottom has split are random in reality; the prediction is their expectation, so it is a
// deterministic function of the row:
//  - landings: 16 fixed placements (4 offsets in the pitch cell x 4 lean directions), averaged; when
//    the row gives `pins`, only the placements that engage that many pins (if any do);
//  - breakage: P(split by insertion k) = 1 - prod_{j<=k} (1 - p_j) from the species' hazards, and the
//    force is the mixture of the sound and the split predictions.
// Identical keys (species, angle, depth, insertion, pins, and the covariates the species' extension
// terms read) are computed once.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include "game/analysis/measured_data.hpp"
#include "systems/insertion/deterioration.hpp"

namespace ikebana::game {

struct InsertionConditions {
    std::string species = "sunflower";    // id or file
    double angle_deg = 45.0;
    std::optional<double> depth_m;        // below the pin tips; none: down to the base plate
    std::uint32_t insertion = 1;
    std::optional<std::uint32_t> pins;
    bool want_outcome = false;
    systems::insertion::Covariates covariates; // for an extended species' terms
};

struct InsertionPrediction {
    double max_force_n = 0.0;     // expected maximum total resistance during the insertion
    double fall_probability = 0.0; // when asked for: share of (weighted) placements that fell
    double broken_probability = 0.0;
};

// A measured row as simulation conditions: the species from `species_override`, else the row's, else
// sunflower; 45 degrees and down to the base plate where the row does not say.
// The trial's own columns only; conditions_of below adds the covariates its species reads.
InsertionConditions conditions_for(const MeasuredTrial& trial, const std::string& species_override, bool want_outcome);

// One placement's push: the largest resistance and the most pins, and whether the stem fell.
struct PlacementResult {
    double force_n = 0.0;
    std::uint32_t pins = 0;
    bool fell = false;
};

// A push sampled each tick: the stem's lowest point and the largest resistance and pins so far.
struct DepthSample {
    double lowest_z_m = 0.0;
    double max_force_n = 0.0;
    std::uint32_t max_pins = 0;
};

class InsertionPredictor {
public:
    // `max_profiles`: simulations kept for rows that share them (about 0.3 MB each).
    explicit InsertionPredictor(std::string kenzan = "standard", std::size_t max_profiles = 256) : kenzan_(std::move(kenzan)), max_profiles_(max_profiles) {}
    Result<InsertionPrediction> predict(const InsertionConditions& conditions);
    // Row i of the data as conditions, with the covariates the species' extension reads and no others
    // (they change nothing, and 500,000 rows of every column were hundreds of MB).
    InsertionConditions conditions_of(const MeasuredData& data, std::size_t i, const std::string& species_override, bool want_outcome);
    // Simulations run so far: pushes to a row's own depth, and pushes to the base plate that rows of
    // any depth are read from.
    [[nodiscard]] std::size_t simulated() const noexcept { return simulated_; }
    // What identifies a simulation: rows with equal keys share one (empty when the species is bad).
    // Rows that differ only in depth (or pins) have one key when they share a push.
    std::string key(const InsertionConditions& conditions);
    // The order to predict rows in so that each distinct simulation runs once, whatever the rows'
    // order: rows that share a key, together (stable: first rows first). In the file's order, rows of
    // 405 conditions in flower order took 3,895 simulations through the 256-entry cache; sorted, 405.
    std::vector<std::size_t> simulation_order(const std::vector<InsertionConditions>& rows);
    // false: each row with a depth is pushed to its own depth (what the shared pushes are checked against).
    void share_depths(bool on) noexcept { share_depths_ = on; }

    // The bench's geometry a row is checked against.
    struct Bench {
        double pin_top_m = 0.0;
        double pin_height_m = 0.0;
        double pitch_m = 0.0;
        double pin_radius_m = 0.0;
        double radius_m = 0.0; // the stem's
    };

private:
    struct Simulation {
        Bench bench;
        double broken_weight = 0.0;
        std::vector<PlacementResult> placements[2];     // sound, split bottom
        std::vector<std::vector<DepthSample>> samples[2]; // when sampled: each placement's push
    };
    Result<Simulation> simulate(const InsertionConditions& conditions, const std::set<std::string>& used, bool sample_depths);
    const std::set<std::string>* covariates_used(const std::string& species, Error* error);
    std::string kenzan_;
    std::size_t simulated_ = 0;
    bool share_depths_ = true;
    [[nodiscard]] bool shares_depth(const InsertionConditions& c) const noexcept { return c.depth_m && !c.want_outcome && share_depths_; }
    std::size_t max_profiles_ = 256;
    std::map<std::string, Simulation> profiles_;
    std::deque<std::string> profile_order_; // oldest first
    std::map<std::string, InsertionPrediction> cache_;
    std::map<std::string, std::set<std::string>> covariates_used_; // by species: what its terms read
    std::map<std::string, Error> failed_species_;                  // by species: why it does not load
};

} // namespace ikebana::game
