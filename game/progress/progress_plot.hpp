#pragma once
// A trainee's progress as a picture: one panel per lesson, the score of each session in order (a
// filled dot for practice, a hollow square for a teacher's demonstration) and, thin behind it, each
// criterion's share of its points, so a teacher sees which part of the form is coming and which is
// not. Drawn with cairo, as PNG or SVG by the file's extension.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "engine/core/result.hpp"
#include "game/progress/progress_db.hpp"

struct _cairo; // cairo_t, without cairo's header

namespace ikebana::game {

enum class PlotFormat { png, svg, pdf };

// One page drawn with cairo, its bytes: PNG an image of `width` x `height` pixels; SVG and PDF that
// many points times `scale` (`draw` sees the same coordinates either way). Cairo's and fontconfig's
// caches are given back after each page.
using CairoDraw = std::function<void(::_cairo* cr)>;
Result<std::string> draw_cairo_page(PlotFormat format, double width, double height, double scale, const CairoDraw& draw);
// Text at (x, y) on such a page in the sans-serif face, `align` 0 left, 0.5 centred, 1 right; its width.
double page_text(::_cairo* cr, double x, double y, const std::string& s, double size, bool bold = false, double align = 0.0);

// A panel of the plot: one trainee's sessions of one lesson, oldest first; the teachers'
// demonstrations of a lesson in a panel of their own (issue 41: with no --trainee, everyone's sessions
// and the demonstrations were joined on one line). Headed by who and the lesson's title.
struct PlotPanel {
    std::string heading; // "Aiko: Sogetsu: Basic Upright Style (moribana)", "demonstrations: ..."
    std::vector<const SessionRecord*> sessions;
};
// In the order each (who, lesson) was first practised.
std::vector<PlotPanel> plot_panels(const std::vector<SessionRecord>& sessions);

// The format a file name asks for (".png" or ".svg", any case); an error naming the file otherwise.
Result<PlotFormat> plot_format_of(const std::filesystem::path& path);
// The image's bytes.
Result<std::string> render_progress_plot(const std::vector<SessionRecord>& sessions, const std::string& title, PlotFormat format);
// Written atomically: a refused or failed write leaves what was there.
Result<void> write_progress_plot(const std::vector<SessionRecord>& sessions, const std::string& title, const std::filesystem::path& out);

} // namespace ikebana::game
