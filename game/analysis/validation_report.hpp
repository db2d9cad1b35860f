#pragma once
// What `ikebana validate` writes: OUT.json (the schema of docs/measured-data.md) and a report folder
// with report.md and its SVG figures, readable on its own.
#include <filesystem>
#include <string>

#include "engine/core/result.hpp"
#include "game/analysis/validation.hpp"

namespace ikebana::game {

std::string validation_json(const ValidationResult& v, const AnalysisOptions& options);
// A few lines for the terminal.
std::string validation_summary(const ValidationResult& v);
// report.md and the figures; written beside and renamed, so an old report is replaced whole.
Result<void> write_validation_report(const ValidationResult& v, const AnalysisOptions& options, const std::filesystem::path& dir,
                                     const std::string& extra_markdown = {});

} // namespace ikebana::game
