#pragma once
// What `ikebana validate` writes: OUT.json (the schema of docs/measured-data.md) and a report folder
// with report.md and its SVG figures, readable on its own.
#include <utility>
#include <vector>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/core/result.hpp"
#include "game/analysis/validation.hpp"

namespace ikebana::game {

std::string validation_json(const ValidationResult& v, const AnalysisOptions& options);
// The other measurements' verdicts as JSON (validation_json's "other_measurements").
nlohmann::ordered_json other_measurements_json(const std::vector<OtherMeasure>& others);
// A few lines for the terminal.
std::string validation_summary(const ValidationResult& v);
// report.md and the figures (file name, contents), for a command that writes them with its other
// outputs, all or none.
std::vector<std::pair<std::string, std::string>> validation_report_files(const ValidationResult& v, const AnalysisOptions& options,
                                                                          const std::string& extra_markdown = {});
// The same written into `dir`: all or none (assets::OutputBatch).
Result<void> write_validation_report(const ValidationResult& v, const AnalysisOptions& options, const std::filesystem::path& dir,
                                     const std::string& extra_markdown = {});

} // namespace ikebana::game
