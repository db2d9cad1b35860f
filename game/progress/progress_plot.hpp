#pragma once
// A trainee's progress as a picture: one panel per lesson, the score of each session in order (a
// filled dot for practice, a hollow square for a teacher's demonstration) and, thin behind it, each
// criterion's share of its points, so a teacher sees which part of the form is coming and which is
// not. Drawn with cairo, as PNG or SVG by the file's extension.
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include "game/progress/progress_db.hpp"

namespace ikebana::game {

enum class PlotFormat { png, svg };

// The format a file name asks for (".png" or ".svg", any case); an error naming the file otherwise.
Result<PlotFormat> plot_format_of(const std::filesystem::path& path);
// The image's bytes.
Result<std::string> render_progress_plot(const std::vector<SessionRecord>& sessions, const std::string& title, PlotFormat format);
// Written atomically: a refused or failed write leaves what was there.
Result<void> write_progress_plot(const std::vector<SessionRecord>& sessions, const std::string& title, const std::filesystem::path& out);

} // namespace ikebana::game
