#include "game/cli/predict_command.hpp"

#include <cstdio>
#include <iostream>
#include <sstream>

#include <unistd.h>

#include "engine/assets/csv_table.hpp"
#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "engine/core/utf8.hpp"
#include "game/analysis/insertion_predictor.hpp"
#include "game/analysis/measured_data.hpp"
#include "game/species/species.hpp"

namespace ikebana::game {

int run_predict(const std::string& input, const std::string& species_override, const std::string& output) {
    // The output is checked before the simulations, not refused after them.
    if (auto ok = assets::check_output_path(output); !ok) {
        std::cerr << "ikebana predict: -o: " << ok.error().message << "\n";
        return 2;
    }
    // A plan of trials not yet run is a normal input: the measured force is for validate.
    auto data = load_measured_data(input, MeasuredForce::optional);
    if (!data) {
        std::cerr << "ikebana predict: " << data.error().message << "\n";
        return 2;
    }
    if (!data->table.note.empty()) std::cerr << "ikebana predict: note: " << data->table.note << "\n";
    InsertionPredictor predictor;
    struct Prediction {
        double force_gf = 0.0;
        double fall_probability = 0.0; // the share of the mixture (placements, sound and split ends) that fell
    };
    std::vector<Prediction> predictions(data->trials.size());
    const bool tty = isatty(fileno(stderr)) != 0;
    std::vector<InsertionConditions> rows;
    for (std::size_t i = 0; i < data->trials.size(); ++i) rows.push_back(predictor.conditions_of(*data, i, species_override, data->has_outcome));
    const auto order = predictor.simulation_order(rows);
    for (std::size_t n = 0; n < order.size(); ++n) {
        const std::size_t i = order[n];
        const auto& t = data->trials[i];
        const auto p = predictor.predict(rows[i]);
        if (!p) {
            std::cerr << "ikebana predict: " << input << ":" << t.line << ": " << p.error().message << "\n";
            return 2;
        }
        predictions[i] = {p->max_force_n / gram_force_n, p->fall_probability};
        if (tty) std::fprintf(stderr, "\rpredicted %zu / %zu rows (%zu simulated)", n + 1, data->trials.size(), predictor.simulated());
    }
    if (tty) std::fprintf(stderr, "\n");
    // The input's lines, unchanged, each data line with the predictions appended.
    auto text = assets::read_text_file(input);
    if (!text) {
        std::cerr << "ikebana predict: " << text.error().message << "\n";
        return 2;
    }
    // Every output is UTF-8: a Windows-1252 (Latin-1) file is written back as the table read it.
    if (!is_utf8(*text)) *text = windows1252_to_utf8(*text);
    std::map<std::size_t, std::size_t> row_of_line;
    // Each row's predictions go at the end of its last line (a quoted cell may hold line breaks).
    for (std::size_t i = 0; i < data->table.last_line_of_row.size(); ++i) row_of_line[data->table.last_line_of_row[i]] = i;
    std::ostringstream out;
    // Split as the table was read (any line ending, no byte-order mark), each line's ending kept.
    std::size_t line_no = 0;
    // A last line without an ending gets the file's own (a CRLF file's last line a CRLF, not an LF).
    std::string_view file_ending = "\n";
    for (const auto& [text_line, ending] : assets::split_lines(*text)) {
        if (!ending.empty()) file_ending = ending;
        ++line_no;
        std::string line(text_line);
        if (line_no == data->table.header_last_line) {
            line += data->has_outcome ? ",predicted_force_gf,predicted_outcome,predicted_fall_probability" : ",predicted_force_gf";
        } else if (const auto it = row_of_line.find(line_no); it != row_of_line.end()) {
            char value[64];
            const Prediction& p = predictions[it->second];
            std::snprintf(value, sizeof value, ",%.2f", p.force_gf);
            line += value;
            if (data->has_outcome) {
                std::snprintf(value, sizeof value, ",%s,%.4f", p.fall_probability > 0.5 ? "fell" : "stood", p.fall_probability);
                line += value;
            }
        }
        out << line << (ending.empty() ? file_ending : ending);
    }
    // Written beside the target and renamed: no half-written output.
    if (auto w = assets::write_text_file(output, out.str()); !w) {
        std::cerr << "ikebana predict: " << w.error().message << "\n";
        return 2;
    }
    std::printf("wrote %zu predictions to %s (%zu distinct conditions simulated)\n", data->trials.size(), output.c_str(), predictor.simulated());
    return 0;
}

void add_predict_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string input;
        std::string species;
        std::string output;
    };
    auto args = std::make_shared<Args>();
    auto* cmd = app.add_subcommand("predict", "Predict every measured insertion through the simulation; rows are written back with predicted_force_gf");
    cmd->add_option("trials", args->input, "Measured or planned trials (CSV, docs/measured-data.md; max_force_gf may be absent or blank)")->required()->check(CLI::ExistingFile);
    cmd->add_option("--species", args->species, "Species id or file for every row (default: the row's species column, else sunflower)");
    cmd->add_option("-o,--output", args->output, "Where to write the rows with predictions")->required();
    cmd->callback([args, &exit_code] { exit_code = run_predict(args->input, args->species, args->output); });
}

} // namespace ikebana::game
