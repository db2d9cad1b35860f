#include "game/progress/progress_plot.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <ctime>
#include <map>

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fontconfig/fontconfig.h>

#include "game/lesson/lesson.hpp"
#include "game/lesson/role_colours.hpp"
#include "engine/assets/files.hpp"

namespace ikebana::game {
namespace {

constexpr double width_px = 1000.0;
constexpr double title_px = 56.0;
constexpr double panel_px = 320.0;
constexpr double left_px = 64.0;
constexpr double legend_px = 250.0;
constexpr double panel_top_px = 34.0;    // the lesson's name above its axes
constexpr double panel_bottom_px = 52.0; // dates under them

std::string criterion_label(const Criterion& c) {
    static const std::map<std::string, std::string> names{
        {"length_mm", "length"}, {"tilt_deg", "tilt"}, {"azimuth_deg", "direction"}, {"region_mm", "place"}, {"match", "match"}};
    const auto it = names.find(c.name);
    return c.stem + " " + (it == names.end() ? c.name : it->second);
}

void text_at(cairo_t* cr, double x, double y, const std::string& s, double size, double align = 0.0, bool bold = false) { page_text(cr, x, y, s, size, bold, align); }

std::string date_of(std::int64_t unix_s, const char* format) {
    const std::time_t t = static_cast<std::time_t>(unix_s);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char text[32];
    std::strftime(text, sizeof text, format, &tm);
    return text;
}

void draw_panel(cairo_t* cr, double top, const std::string& who_and_lesson, const std::vector<const SessionRecord*>& sessions) {
    const double x0 = left_px, x1 = width_px - legend_px;
    const double y0 = top + panel_top_px, y1 = top + panel_px - panel_bottom_px;
    const std::size_t n = sessions.size();
    const auto x_of = [&](std::size_t i) { return x0 + (static_cast<double>(i) + 0.5) * (x1 - x0) / static_cast<double>(n); };
    const auto y_of = [&](double score) { return y1 - std::clamp(score, 0.0, 100.0) / 100.0 * (y1 - y0); };

    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    char heading[200];
    std::snprintf(heading, sizeof heading, "%s: %zu session%s, last %.1f / 100", who_and_lesson.c_str(), n, n == 1 ? "" : "s", sessions.back()->result.score);
    text_at(cr, x0, top + 22.0, heading, 15.0, 0.0, true);

    // Axes and grid: every 25 points, and the 90 that every band earns, dashed.
    cairo_set_line_width(cr, 1.0);
    for (int s = 0; s <= 100; s += 25) {
        cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
        cairo_move_to(cr, x0, y_of(s) + 0.5);
        cairo_line_to(cr, x1, y_of(s) + 0.5);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
        text_at(cr, x0 - 8.0, y_of(s) + 4.0, std::to_string(s), 11.0, 1.0);
    }
    const double dash[] = {6.0, 4.0};
    cairo_set_dash(cr, dash, 2, 0.0);
    cairo_set_source_rgb(cr, 0.2, 0.6, 0.3);
    cairo_move_to(cr, x0, y_of(90.0) + 0.5);
    cairo_line_to(cr, x1, y_of(90.0) + 0.5);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0.0);
    text_at(cr, x1 - 4.0, y_of(90.0) - 4.0, "90: inside every band", 10.0, 1.0);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    cairo_save(cr);
    cairo_translate(cr, 16.0, 0.5 * (y0 + y1));
    cairo_rotate(cr, -M_PI / 2.0);
    text_at(cr, 0.0, 0.0, "score; each criterion: % of its points", 11.0, 0.5);
    cairo_restore(cr);

    // Dates under the sessions, at most about ten of them.
    const std::size_t every = std::max<std::size_t>(1, (n + 9) / 10);
    for (std::size_t i = 0; i < n; i += every) {
        cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
        text_at(cr, x_of(i), y1 + 16.0, date_of(sessions[i]->started_unix_s, "%b %d"), 10.0, 0.5);
        text_at(cr, x_of(i), y1 + 29.0, date_of(sessions[i]->started_unix_s, "%H:%M"), 10.0, 0.5);
    }
    text_at(cr, 0.5 * (x0 + x1), y1 + 46.0, "sessions in order (UTC)", 11.0, 0.5);

    // Each criterion's trend, in the order the lesson gives them: a colour per stem (its role's), a dash per kind
    // of criterion (length solid, tilt dashed, direction dotted, place dash-dot).
    struct Trend {
        std::string label;
        std::size_t colour;
        std::string kind;
        std::vector<std::pair<std::size_t, double>> points;
    };
    std::vector<Trend> trends;
    std::vector<std::string> stems;
    for (std::size_t i = 0; i < n; ++i) {
        for (const auto& c : sessions[i]->result.criteria) {
            if (c.max_points <= 0.0) continue;
            const auto label = criterion_label(c);
            auto it = std::find_if(trends.begin(), trends.end(), [&](const Trend& t) { return t.label == label; });
            if (it == trends.end()) {
                auto stem = std::find(stems.begin(), stems.end(), c.stem);
                if (stem == stems.end()) stem = stems.insert(stems.end(), c.stem);
                trends.push_back({label, static_cast<std::size_t>(stem - stems.begin()), c.name, {}});
                it = trends.end() - 1;
            }
            it->points.emplace_back(i, 100.0 * c.points / c.max_points);
        }
    }
    const auto dashed = [&](const std::string& kind) {
        static const double tilt[] = {7.0, 4.0}, direction[] = {2.0, 3.0}, place[] = {8.0, 3.0, 2.0, 3.0};
        if (kind == "tilt_deg") cairo_set_dash(cr, tilt, 2, 0.0);
        else if (kind == "azimuth_deg") cairo_set_dash(cr, direction, 2, 0.0);
        else if (kind == "region_mm") cairo_set_dash(cr, place, 4, 0.0);
        else cairo_set_dash(cr, nullptr, 0, 0.0);
    };
    const std::size_t shown = std::min<std::size_t>(trends.size(), 14);
    for (std::size_t k = 0; k < shown; ++k) {
        const Trend& t = trends[k];
        // The stem's role colour, as the window draws it (stems come in the lesson's order).
        const glm::vec3 c = role_colour(t.colour).rgb;
        cairo_set_source_rgba(cr, c.r, c.g, c.b, 0.85);
        cairo_set_line_width(cr, 1.6);
        dashed(t.kind);
        // Lines a little apart so equal trends (all full marks) stay visible side by side.
        const double nudge = (static_cast<double>(k) - 0.5 * static_cast<double>(shown - 1)) * 1.2;
        for (std::size_t p = 0; p < t.points.size(); ++p) {
            const double x = x_of(t.points[p].first), y = y_of(t.points[p].second) + nudge;
            if (p == 0) cairo_move_to(cr, x, y);
            else cairo_line_to(cr, x, y);
        }
        cairo_stroke(cr);
        if (t.points.size() == 1) {
            cairo_arc(cr, x_of(t.points[0].first) + 9.0, y_of(t.points[0].second) + nudge, 2.0, 0.0, 2.0 * M_PI);
            cairo_fill(cr);
        }
        // Its legend entry.
        const double ly = y0 + 15.0 * static_cast<double>(k) + 8.0;
        cairo_move_to(cr, x1 + 18.0, ly - 4.0);
        cairo_line_to(cr, x1 + 40.0, ly - 4.0);
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0.0);
        cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
        text_at(cr, x1 + 46.0, ly, t.label, 11.0);
    }
    cairo_set_dash(cr, nullptr, 0, 0.0);
    if (trends.size() > shown) {
        cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
        text_at(cr, x1 + 46.0, y0 + 15.0 * static_cast<double>(shown) + 8.0, "(" + std::to_string(trends.size() - shown) + " more not drawn)", 10.0);
    }

    // The score on top: joined, practice as dots, demonstrations as hollow squares.
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_set_line_width(cr, 3.0);
    for (std::size_t i = 0; i < n; ++i) {
        if (i == 0) cairo_move_to(cr, x_of(i), y_of(sessions[i]->result.score));
        else cairo_line_to(cr, x_of(i), y_of(sessions[i]->result.score));
    }
    cairo_stroke(cr);
    for (std::size_t i = 0; i < n; ++i) {
        const double x = x_of(i), y = y_of(sessions[i]->result.score);
        if (sessions[i]->kind == "demonstration") {
            cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
            cairo_rectangle(cr, x - 5.0, y - 5.0, 10.0, 10.0);
            cairo_fill_preserve(cr);
            cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
            cairo_set_line_width(cr, 2.0);
            cairo_stroke(cr);
        } else {
            cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
            cairo_arc(cr, x, y, 5.0, 0.0, 2.0 * M_PI);
            cairo_fill(cr);
        }
        // Each point its score (its date is under the axis), while they fit.
        if (n <= 20) {
            cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
            char score[16];
            std::snprintf(score, sizeof score, "%.0f", sessions[i]->result.score);
            // Under a point near the top (above it, it would run into the panel's heading).
            const bool high = sessions[i]->result.score > 92.0;
            text_at(cr, x, high ? y + 20.0 : y - 10.0, score, 11.0, 0.5, true);
        }
    }
    // The markers' legend, under the criteria's.
    const double ly = y1 - 20.0;
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_arc(cr, x1 + 29.0, ly - 4.0, 5.0, 0.0, 2.0 * M_PI);
    cairo_fill(cr);
    text_at(cr, x1 + 46.0, ly, "score, practice", 11.0);
    cairo_set_line_width(cr, 2.0);
    cairo_rectangle(cr, x1 + 24.0, ly + 11.0, 10.0, 10.0);
    cairo_stroke(cr);
    text_at(cr, x1 + 46.0, ly + 20.0, "score, demonstration", 11.0);
}

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

} // namespace

std::vector<PlotPanel> plot_panels(const std::vector<SessionRecord>& sessions) {
    std::vector<PlotPanel> panels;
    std::map<std::pair<std::string, std::string>, std::size_t> at;
    std::map<std::string, std::string> titles; // by lesson id: "School: Title", or the id when it does not load
    for (const auto& s : sessions) {
        const std::string who = s.kind == "demonstration" ? "demonstrations" : (s.trainee.empty() ? "(no name)" : s.trainee);
        const auto [it, added] = at.emplace(std::pair{who, s.lesson}, panels.size());
        if (added) {
            auto title = titles.find(s.lesson);
            if (title == titles.end()) {
                const auto lesson = load_lesson(s.lesson);
                title = titles.emplace(s.lesson, lesson ? lesson->school + ": " + lesson->title : s.lesson).first;
            }
            panels.push_back({who + ": " + title->second, {}});
        }
        panels[it->second].sessions.push_back(&s);
    }
    return panels;
}

Result<PlotFormat> plot_format_of(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".png") return PlotFormat::png;
    if (ext == ".svg") return PlotFormat::svg;
    return make_error(ErrorCode::invalid_argument, path.string() + ": a plot is written as .png or .svg");
}

Result<std::string> render_progress_plot(const std::vector<SessionRecord>& sessions, const std::string& title, PlotFormat format) {
    const std::vector<PlotPanel> panels = plot_panels(sessions);
    const double height_px = title_px + panel_px * static_cast<double>(std::max<std::size_t>(1, panels.size()));
    return draw_cairo_page(format, width_px, height_px, 1.0, [&](cairo_t* cr) {
        cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
        cairo_paint(cr);
        cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
        text_at(cr, left_px, 34.0, title, 20.0, 0.0, true);
        if (panels.empty()) {
            cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
            text_at(cr, 0.5 * width_px, title_px + 0.5 * panel_px, "no sessions yet", 16.0, 0.5);
        }
        for (std::size_t i = 0; i < panels.size(); ++i) draw_panel(cr, title_px + panel_px * static_cast<double>(i), panels[i].heading, panels[i].sessions);
    });
}

double page_text(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold, double align) {
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents_t e;
    cairo_text_extents(cr, s.c_str(), &e);
    cairo_move_to(cr, x - align * e.x_advance, y);
    cairo_show_text(cr, s.c_str());
    return e.x_advance;
}

Result<std::string> draw_cairo_page(PlotFormat format, double width, double height, double scale, const CairoDraw& draw) {
    std::string bytes;
    cairo_surface_t* surface = format == PlotFormat::svg   ? cairo_svg_surface_create_for_stream(append, &bytes, width * scale, height * scale)
                               : format == PlotFormat::pdf ? cairo_pdf_surface_create_for_stream(append, &bytes, width * scale, height * scale)
                                                           : cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(width), static_cast<int>(height));
    cairo_t* cr = cairo_create(surface);
    if (format != PlotFormat::png) cairo_scale(cr, scale, scale);
    draw(cr);
    const cairo_status_t drawn = cairo_status(cr);
    cairo_destroy(cr);
    cairo_status_t written = CAIRO_STATUS_SUCCESS;
    if (format == PlotFormat::png) written = cairo_surface_write_to_png_stream(surface, append, &bytes);
    cairo_surface_finish(surface);
    const cairo_status_t finished = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    // Cairo keeps the fonts it looked up, and fontconfig its configuration, for the process's life:
    // given back here (the next page looks them up again), so that LeakSanitizer sees no leak of ours
    // among theirs. The plots and the session reports are cairo's and fontconfig's only users.
    cairo_debug_reset_static_data();
    FcFini();
    for (const auto status : {drawn, written, finished}) {
        if (status != CAIRO_STATUS_SUCCESS) return make_error(ErrorCode::io_error, std::string("the page could not be drawn: ") + cairo_status_to_string(status));
    }
    return bytes;
}

Result<void> write_progress_plot(const std::vector<SessionRecord>& sessions, const std::string& title, const std::filesystem::path& out) {
    const auto format = plot_format_of(out);
    if (!format) return format.error();
    if (auto ok = assets::check_output_path(out); !ok) return ok;
    auto bytes = render_progress_plot(sessions, title, *format);
    if (!bytes) return bytes.error();
    return assets::write_file_atomically(out, *bytes);
}

} // namespace ikebana::game
