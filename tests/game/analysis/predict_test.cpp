#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "game/analysis/insertion_predictor.hpp"
#include "game/analysis/measured_data.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/predict_command.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {
std::string temp(const std::string& name) { return (std::filesystem::temp_directory_path() / ("ikebana_predict_" + name)).string(); }
std::string write(const std::string& name, const std::string& text) {
    const auto path = temp(name);
    std::ofstream(path) << text;
    return path;
}
std::vector<std::string> lines(const std::string& path) {
    std::vector<std::string> out;
    std::istringstream in(*assets::read_text_file(path));
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}
} // namespace

TEST(Predict, RowsComeBackUnchangedWithThePredictionAppended) {
    const auto input = write("in.csv", "# a comment stays\nflower_id,insertion,max_force_gf,room,note\nA,1,480,dry,\"first, gently\"\nA,3,410,dry,x\n");
    const auto output = temp("out.csv");
    ASSERT_EQ(run_predict(input, "", output), 0);
    const auto in = lines(input);
    const auto out = lines(output);
    ASSERT_EQ(out.size(), in.size());
    EXPECT_EQ(out[0], in[0]);
    EXPECT_EQ(out[1], in[1] + ",predicted_force_gf");
    for (std::size_t i = 2; i < in.size(); ++i) {
        ASSERT_EQ(out[i].rfind(in[i] + ",", 0), 0u) << "the row itself is untouched, extra columns included";
    }
    const double first = std::stod(out[2].substr(out[2].rfind(',') + 1));
    const double third = std::stod(out[3].substr(out[3].rfind(',') + 1));
    EXPECT_GT(first, 100.0) << "grams-force for several pins";
    EXPECT_GT(first, third) << "the third insertion resists less (Table 2, and the bottom may have split)";
}

TEST(Predict, SameRowSamePredictionWhateverElseIsInTheFile) {
    const auto alone = write("alone.csv", "flower_id,insertion,max_force_gf\nA,2,460\n");
    const auto crowd = write("crowd.csv", "flower_id,insertion,max_force_gf\nB,5,300\nC,1,480\nA,2,460\n");
    ASSERT_EQ(run_predict(alone, "", temp("alone_out.csv")), 0);
    ASSERT_EQ(run_predict(crowd, "", temp("crowd_out.csv")), 0);
    const auto a = lines(temp("alone_out.csv"));
    const auto c = lines(temp("crowd_out.csv"));
    EXPECT_EQ(a[1], c[3]);
    ASSERT_EQ(run_predict(crowd, "", temp("crowd_again.csv")), 0);
    EXPECT_EQ(lines(temp("crowd_again.csv")), c) << "deterministic run to run";
}

// With an outcome column, each row gets the outcome the mixture votes for and its chance of falling (the
// share of the mixture that fell): the vote is "fell" exactly when the chance is above one half.
TEST(Predict, OutcomeColumnGetsAPredictedOutcomeAndAChanceOfFalling) {
    const auto input = write("outcome.csv", "flower_id,insertion,max_force_gf,outcome\nA,1,480,stood\nB,1,470,stood\nC,9,300,fell\n");
    ASSERT_EQ(run_predict(input, "", temp("outcome_out.csv")), 0);
    const auto out = lines(temp("outcome_out.csv"));
    EXPECT_EQ(out[0], "flower_id,insertion,max_force_gf,outcome,predicted_force_gf,predicted_outcome,predicted_fall_probability");
    for (std::size_t i = 1; i < out.size(); ++i) {
        const auto comma = out[i].rfind(',');
        ASSERT_NE(comma, std::string::npos);
        const double p = std::stod(out[i].substr(comma + 1));
        EXPECT_GE(p, 0.0);
        EXPECT_LE(p, 1.0);
        const std::string vote = out[i].substr(0, comma).substr(out[i].substr(0, comma).rfind(',') + 1);
        EXPECT_EQ(vote, p > 0.5 ? "fell" : "stood") << out[i];
    }
}

// Issue 57: a term on what holds a stem at rest ("applies_to": "hold") moves the chance of falling and
// never the force a gauge reads as the stem is pushed in: held at half, stems at 45 degrees that stood
// fall; the predicted forces are the same to the last digit.
TEST(Predict, ATermOnTheHoldingAloneMovesTheChanceOfFallingAndNotTheForce) {
    auto species = nlohmann::json::parse(*assets::read_text_file(asset_dir() / "species" / "sunflower.json"));
    species["id"] = "held_half";
    species["deterioration"] = {{"model", "extended"},
                                {"base", "paper_baseline"},
                                {"terms", {{{"covariate", "insertion"}, {"form", "constant"}, {"coefficient", std::log(0.5)}, {"applies_to", "hold"}}}}};
    const auto species_file = write("held_half.json", species.dump());
    const auto input = write("held.csv", "flower_id,insertion,max_force_gf,outcome,angle_deg\nA,1,480,stood,45\nA,2,470,stood,45\n");
    ASSERT_EQ(run_predict(input, "", temp("held_base.csv")), 0);
    ASSERT_EQ(run_predict(input, species_file, temp("held_half_out.csv")), 0);
    const auto base = lines(temp("held_base.csv"));
    const auto half = lines(temp("held_half_out.csv"));
    ASSERT_EQ(base.size(), 3u);
    ASSERT_EQ(half.size(), 3u);
    const auto cells = [](const std::string& line) {
        std::vector<std::string> out;
        std::stringstream in(line);
        for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
        return out;
    };
    for (std::size_t i = 1; i < 3; ++i) {
        const auto b = cells(base[i]);
        const auto h = cells(half[i]);
        ASSERT_EQ(b.size(), 8u);
        ASSERT_EQ(h.size(), 8u);
        EXPECT_EQ(h[5], b[5]) << "the force as it is pushed in, row " << i;
        EXPECT_GT(std::stod(h[7]), std::stod(b[7])) << "a better chance of falling, row " << i;
    }
    EXPECT_EQ(cells(base[1])[6], "stood");
    EXPECT_EQ(cells(half[1])[6], "fell");
}

// A term on the holding that reads a column of the row: rows that differ only in that column are two
// simulations (the predictor once keyed and filled rows by the push's terms alone, so a hold term on
// a column was evaluated without it and every row shared one simulation).
TEST(Predict, ATermOnTheHoldingReadsItsColumnFromEachRow) {
    auto species = nlohmann::json::parse(*assets::read_text_file(asset_dir() / "species" / "sunflower.json"));
    species["id"] = "held_by_water";
    species["deterioration"] = {{"model", "extended"},
                                {"base", "paper_baseline"},
                                {"terms", {{{"covariate", "water"}, {"form", "linear"}, {"coefficient", -3.0}, {"applies_to", "hold"}}}}};
    const auto species_file = write("held_by_water.json", species.dump());
    const auto input = write("water.csv", "flower_id,insertion,max_force_gf,outcome,angle_deg,depth_mm,water\nA,1,480,stood,45,12,0\nB,1,480,stood,45,12,0.4\n");
    ASSERT_EQ(run_predict(input, species_file, temp("water_out.csv")), 0);
    const auto out = lines(temp("water_out.csv"));
    ASSERT_EQ(out.size(), 3u);
    const auto chance = [](const std::string& line) { return std::stod(line.substr(line.rfind(',') + 1)); };
    EXPECT_LT(chance(out[1]), 0.5) << "held as the species says at water 0: " << out[1];
    EXPECT_GT(chance(out[2]), chance(out[1])) << "held at exp(-1.2) = 0.30 with water 0.4, it falls more readily: " << out[2];
}

TEST(Predict, BadInputNamesFileLineAndColumnAndWritesNothing) {
    const auto bad = write("bad.csv", "flower_id,insertion,max_force_gf\nA,1,480\nA,two,460\n");
    const auto data = load_measured_data(bad);
    ASSERT_FALSE(data);
    EXPECT_NE(data.error().message.find("bad.csv:3: column 'insertion': expected a number, got 'two'"), std::string::npos)
        << data.error().message;
    const auto output = temp("never.csv");
    std::filesystem::remove(output);
    EXPECT_NE(run_predict(bad, "", output), 0);
    EXPECT_FALSE(std::filesystem::exists(output));
    const auto missing = load_measured_data(write("missing.csv", "flower_id,max_force_gf\nA,480\n"));
    ASSERT_FALSE(missing);
    EXPECT_NE(missing.error().message.find("missing the required column 'insertion'"), std::string::npos);
    const auto zero = load_measured_data(write("zero.csv", "flower_id,insertion,max_force_gf\nA,0,480\n"));
    EXPECT_FALSE(zero);
    const auto outcome = load_measured_data(write("out.csv", "flower_id,insertion,max_force_gf,outcome\nA,1,480,wilted\n"));
    ASSERT_FALSE(outcome);
    EXPECT_NE(outcome.error().message.find("expected stood, fell or broke"), std::string::npos);
}

// Issue 17: predicting before measuring is a normal use. A plan has no max_force_gf column, or blank
// cells where a trial has not been run yet; validate, which compares with measurements, still needs it.
TEST(Predict, APlanOfTrialsNotYetRunIsPredicted) {
    const auto plan = write("plan.csv", "flower_id,insertion,angle_deg\nA,1,90\nA,2,90\nB,1,60\n");
    ASSERT_EQ(run_predict(plan, "", temp("plan_out.csv")), 0);
    const auto out = lines(temp("plan_out.csv"));
    ASSERT_EQ(out.size(), 4u);
    EXPECT_EQ(out[0], "flower_id,insertion,angle_deg,predicted_force_gf");
    const auto measured = write("measured.csv", "flower_id,insertion,max_force_gf,angle_deg\nA,1,480,90\nA,2,460,90\nB,1,300,60\n");
    ASSERT_EQ(run_predict(measured, "", temp("measured_out.csv")), 0);
    const auto same = lines(temp("measured_out.csv"));
    for (std::size_t i = 1; i < 4; ++i) {
        EXPECT_EQ(out[i].substr(out[i].rfind(',')), same[i].substr(same[i].rfind(','))) << "the measurement plays no part in the prediction";
    }
    // Half run: blank cells are trials to come; a cell that is there must still be a force.
    const auto half = write("half.csv", "flower_id,insertion,max_force_gf\nA,1,480\nA,2,\n");
    ASSERT_EQ(run_predict(half, "", temp("half_out.csv")), 0);
    EXPECT_EQ(lines(temp("half_out.csv")).size(), 3u);
    const auto bad = load_measured_data(write("plan_bad.csv", "flower_id,insertion,max_force_gf\nA,1,-3\n"), MeasuredForce::optional);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("plan_bad.csv:2: column 'max_force_gf': expected a number in [0, 100000], got '-3'"), std::string::npos) << bad.error().message;
    const auto for_validate = load_measured_data(plan);
    ASSERT_FALSE(for_validate);
    EXPECT_NE(for_validate.error().message.find("plan.csv: missing the required column 'max_force_gf'"), std::string::npos);
    const auto blank_for_validate = load_measured_data(half);
    ASSERT_FALSE(blank_for_validate);
    EXPECT_NE(blank_for_validate.error().message.find("half.csv:3: column 'max_force_gf': expected a positive number"), std::string::npos)
        << blank_for_validate.error().message;
}

TEST(Predict, UnknownColumnsBecomeCovariates) {
    const auto data = load_measured_data(write("cov.csv", "flower_id,insertion,max_force_gf,room_c,batch\nA,1,480,21.5,north\n"));
    ASSERT_TRUE(data) << data.error().message;
    EXPECT_EQ(data->covariates_of(0).numeric.at("room_c"), 21.5);
    EXPECT_EQ(data->covariates_of(0).category.at("batch"), "north");
    EXPECT_EQ(data->covariates_of(0).numeric.at("insertion"), 1.0);
}

TEST(Predict, DepthsBeyondThePinsAndPinCountsNoStemCanTouchAreRefused) {
    // 50 mm once gave 494 gf (the stem pushed through the base); pins 0 and 999 once meant "any".
    const auto deep = write("deep.csv", "flower_id,insertion,max_force_gf,depth_mm\nA,1,480,50\n");
    const auto output = temp("deep_out.csv");
    std::filesystem::remove(output);
    EXPECT_NE(run_predict(deep, "", output), 0);
    EXPECT_FALSE(std::filesystem::exists(output));
    InsertionPredictor predictor;
    MeasuredTrial trial;
    trial.insertion = 1;
    trial.max_force_gf = 480;
    trial.depth_mm = 50;
    const auto too_deep = predictor.predict(conditions_for(trial, "sunflower", false));
    ASSERT_FALSE(too_deep);
    EXPECT_EQ(too_deep.error().message, "depth_mm: 50 mm is deeper than the kenzan's pins are tall (13 mm); the stem would be pushed into the base plate");
    trial.depth_mm.reset();
    trial.pins = 999;
    const auto many = predictor.predict(conditions_for(trial, "sunflower", false));
    ASSERT_FALSE(many);
    EXPECT_NE(many.error().message.find("pins: 999 is more than a 7.5 mm stem at 45 degrees can touch on this kenzan (at most "), std::string::npos)
        << many.error().message;
    const auto zero = load_measured_data(write("zero_pins.csv", "flower_id,insertion,max_force_gf,pins\nA,1,480,0\n"));
    ASSERT_FALSE(zero);
    EXPECT_NE(zero.error().message.find("zero_pins.csv:2: column 'pins': expected an integer in [1, 1000], got '0'"), std::string::npos)
        << zero.error().message;
}

// Rows that differ in depth are read off one push to the base plate: a tick at a time, interpolated to
// each row's stop. Against each row pushed to its own depth (the way every row was simulated before),
// at two angles, a first and a third insertion (the split bottom mixed in) and depths across the pins,
// every prediction is within 1 %, with a quarter of the simulations.
TEST(Predict, RowsOfAnyDepthReadOffOnePushAgreeWithEachRowPushedToItsOwnDepth) {
    InsertionPredictor shared;
    InsertionPredictor own;
    own.share_depths(false);
    std::size_t rows = 0;
    for (const double angle : {45.0, 70.0}) {
        for (const std::uint32_t insertion : {1u, 3u}) {
            for (const double depth_mm : {3.1, 8.37, 10.93, 12.9}) {
                InsertionConditions c;
                c.angle_deg = angle;
                c.insertion = insertion;
                c.depth_m = depth_mm * 1e-3;
                const auto a = shared.predict(c);
                const auto b = own.predict(c);
                ASSERT_TRUE(a && b);
                ++rows;
                EXPECT_GT(b->max_force_n, 0.0);
                EXPECT_NEAR(a->max_force_n, b->max_force_n, 0.01 * b->max_force_n)
                    << angle << " deg, insertion " << insertion << ", " << depth_mm << " mm";
                EXPECT_EQ(a->broken_probability, b->broken_probability);
            }
        }
    }
    EXPECT_EQ(own.simulated(), rows);
    EXPECT_EQ(shared.simulated(), rows / 4) << "one push per angle and insertion";
    InsertionConditions shallow, deep;
    shallow.depth_m = 0.004;
    deep.depth_m = 0.0121;
    EXPECT_EQ(shared.key(shallow), shared.key(deep)) << "one simulation, so one key (validate counts keys)";
    EXPECT_NE(own.key(shallow), own.key(deep));
}

// Each distinct condition is simulated once whatever the rows' order: six angles, each flower (at a
// depth of its own) in turn at every angle, through a cache of four pushes (the 256-entry cache in small). In the file's order
// the first-in-first-out cache let every angle go before its next row and simulated 18 times;
// grouped by simulation_order, 6, with the same predictions as each row alone.
TEST(Predict, EachDistinctConditionIsSimulatedOnceWhateverTheRowsOrder) {
    std::vector<InsertionConditions> rows;
    for (int flower = 0; flower < 3; ++flower) {
        for (int a = 0; a < 6; ++a) {
            InsertionConditions c;
            c.angle_deg = 20.0 + 5.0 * a;
            c.depth_m = 0.008 + 0.002 * flower; // each flower's own depth: rows read one push per angle
            rows.push_back(c);
        }
    }
    InsertionPredictor in_file_order("standard", 4);
    std::vector<double> as_read;
    for (const auto& r : rows) {
        const auto p = in_file_order.predict(r);
        ASSERT_TRUE(p) << p.error().message;
        as_read.push_back(p->max_force_n);
    }
    EXPECT_EQ(in_file_order.simulated(), 18u) << "the cache of four forgot each angle before its next row";
    InsertionPredictor grouped("standard", 4);
    const auto order = grouped.simulation_order(rows);
    ASSERT_EQ(order.size(), rows.size());
    std::vector<double> predicted(rows.size(), 0.0);
    for (const std::size_t i : order) {
        const auto p = grouped.predict(rows[i]);
        ASSERT_TRUE(p) << p.error().message;
        predicted[i] = p->max_force_n;
    }
    EXPECT_EQ(grouped.simulated(), 6u);
    EXPECT_EQ(predicted, as_read) << "the same predictions, row for row";
}
