#include "game/session/session_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include <cairo.h>

#include "engine/assets/files.hpp"
#include "game/lesson/role_colours.hpp"
#include "game/progress/progress_plot.hpp"
#include "game/session/lesson_session.hpp"
#include "game/training/stem_geometry.hpp"
#include "game/world/lesson_scene.hpp"

namespace ikebana::game {

namespace {

// One page, A4 landscape: 1123 x 794 at 96 dpi in the PNG, 842 x 595 pt in the PDF (scaled 0.75).
constexpr double page_w = 1123.0, page_h = 794.0;

bool same_folder(const std::filesystem::path& a, const std::filesystem::path& b) {
    std::error_code ea, eb;
    const auto ca = std::filesystem::weakly_canonical(a, ea), cb = std::filesystem::weakly_canonical(b, eb);
    return !ea && !eb && ca == cb;
}

// "2026-11-28 09:14", from the database's ISO time.
std::string date_of(std::int64_t unix_s) {
    if (unix_s <= 0) return "";
    std::string t = iso_utc(unix_s).substr(0, 16);
    t[10] = ' ';
    return t;
}

void colour(cairo_t* cr, const glm::vec3& c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }


// Words laid into lines no wider than `width`; the y below the last.
double wrapped(cairo_t* cr, double x, double y, const std::string& s, double size, double width) {
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    std::istringstream words(s);
    std::string word, line;
    const auto flush = [&] {
        if (line.empty()) return;
        cairo_move_to(cr, x, y);
        cairo_show_text(cr, line.c_str());
        y += size * 1.25;
        line.clear();
    };
    while (words >> word) {
        const std::string longer = line.empty() ? word : line + " " + word;
        cairo_text_extents_t e;
        cairo_text_extents(cr, longer.c_str(), &e);
        if (e.x_advance > width && !line.empty()) {
            flush();
            line = word;
        } else {
            line = longer;
        }
    }
    flush();
    return y;
}

// The role's colour (its place in the lesson), grey for a supporting stem.
glm::vec3 stem_colour(const LessonDef& l, const std::string& role) {
    for (std::size_t i = 0; i < l.stems.size(); ++i) {
        if (l.stems[i].role == role) return role_colour(i).rgb;
    }
    return {0.45f, 0.45f, 0.45f};
}

// A view of the container: `front` (x across, z up) or from above (x across, y away, the viewer below).
struct View {
    double x0, y0, w, h; // the panel
    bool front = true;
    double scale = 1.0;  // px per metre
    double cx = 0.0, cy = 0.0; // the panel's point for the container's centre (front: its floor)
    [[nodiscard]] std::pair<double, double> at(glm::dvec3 p) const {
        return front ? std::pair{cx + p.x * scale, cy - p.z * scale} : std::pair{cx + p.x * scale, cy - p.y * scale};
    }
};

// A stem's points in container coordinates (x right, y away, z up from the container's floor).
std::vector<glm::dvec3> container_points(const SessionReport& r, const Arrangement& a, const ArrangementStem& s) {
    const glm::dvec2 offset = a.kenzan_offset_m.value_or(r.lesson.kenzan_offset_m);
    const bool vase = r.lesson.container.shape == ContainerShape::vase;
    const double lift = (vase ? r.lesson.container.depth_m : 0.0) + r.kenzan.plate_thickness_m;
    std::vector<glm::dvec3> points;
    for (const auto& p : training::polyline(s)) points.push_back({p.x + offset.x, p.y + offset.y, p.z + lift});
    return points;
}

void draw_stems(cairo_t* cr, const View& v, const SessionReport& r, const Arrangement& a, bool model) {
    for (const auto& s : a.stems) {
        const auto points = container_points(r, a, s);
        if (points.size() < 2) continue;
        colour(cr, stem_colour(r.lesson, s.role));
        cairo_set_line_width(cr, model ? 1.5 : 3.5);
        const double model_dash[] = {5.0, 4.0}, fallen_dash[] = {1.5, 3.0};
        if (model) cairo_set_dash(cr, model_dash, 2, 0.0);
        else if (!s.standing) cairo_set_dash(cr, fallen_dash, 2, 0.0);
        const auto [x, y] = v.at(points.front());
        cairo_move_to(cr, x, y);
        for (std::size_t i = 1; i < points.size(); ++i) {
            const auto [px, py] = v.at(points[i]);
            cairo_line_to(cr, px, py);
        }
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0.0);
        if (!model) {
            const auto [tx, ty] = v.at(points.back());
            cairo_new_path(cr);
            cairo_arc(cr, tx, ty, 4.0, 0.0, 2.0 * 3.14159265358979323846);
            cairo_fill(cr);
        }
    }
}

void draw_view(cairo_t* cr, View v, const SessionReport& r) {
    const auto& box = r.lesson.container;
    const bool vase = box.shape == ContainerShape::vase;
    const double depth_m = box.shape == ContainerShape::rectangular ? box.front_to_back_m : box.width_m;
    // Fit the container and every stem, the arrangement's and the model's.
    double reach_x = 0.5 * box.width_m, reach_up = v.front ? box.depth_m : 0.5 * depth_m, reach_down = v.front ? 0.0 : 0.5 * depth_m;
    for (const Arrangement* a : {&r.session.result.arrangement, &r.model}) {
        for (const auto& s : a->stems) {
            for (const auto& p : container_points(r, *a, s)) {
                reach_x = std::max(reach_x, std::abs(p.x));
                reach_up = std::max(reach_up, v.front ? p.z : p.y);
                reach_down = std::max(reach_down, v.front ? 0.0 : -p.y);
            }
        }
    }
    v.scale = std::min((v.w - 20.0) / (2.0 * reach_x), (v.h - 40.0) / (reach_up + reach_down));
    v.cx = v.x0 + 0.5 * v.w;
    v.cy = v.y0 + 24.0 + reach_up * v.scale;
    cairo_set_source_rgb(cr, 0.97, 0.96, 0.93);
    cairo_rectangle(cr, v.x0, v.y0, v.w, v.h);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    page_text(cr, v.x0 + 8.0, v.y0 + 16.0, v.front ? "from the front" : "from above (you: below)", 12.0, true);
    // The container and the kenzan.
    cairo_set_source_rgb(cr, 0.55, 0.5, 0.45);
    cairo_set_line_width(cr, 2.0);
    const glm::dvec2 k = r.session.result.arrangement.kenzan_offset_m.value_or(r.lesson.kenzan_offset_m);
    const double lift = vase ? box.depth_m : 0.0;
    if (v.front) {
        const auto [l, b] = v.at({-0.5 * box.width_m, 0, 0});
        const auto [rt, t] = v.at({0.5 * box.width_m, 0, box.depth_m});
        cairo_move_to(cr, l, t);
        cairo_line_to(cr, l, b);
        cairo_line_to(cr, rt, b);
        cairo_line_to(cr, rt, t);
        cairo_stroke(cr);
        const auto [kl, kb] = v.at({k.x - 0.5 * r.kenzan.size_m.x, 0, lift});
        const auto [kr, kt] = v.at({k.x + 0.5 * r.kenzan.size_m.x, 0, lift + r.kenzan.plate_thickness_m});
        cairo_rectangle(cr, kl, kt, kr - kl, kb - kt);
        cairo_fill(cr);
    } else {
        if (box.shape == ContainerShape::rectangular) {
            const auto [l, f] = v.at({-0.5 * box.width_m, -0.5 * depth_m, 0});
            const auto [rt, bk] = v.at({0.5 * box.width_m, 0.5 * depth_m, 0});
            cairo_rectangle(cr, l, bk, rt - l, f - bk);
        } else {
            cairo_new_path(cr); // the heading's text left a current point: no line from it to the circle
            cairo_arc(cr, v.cx, v.cy, 0.5 * box.width_m * v.scale, 0.0, 2.0 * 3.14159265358979323846);
        }
        cairo_stroke(cr);
        const auto [kl, kf] = v.at({k.x - 0.5 * r.kenzan.size_m.x, k.y - 0.5 * r.kenzan.size_m.y, 0});
        const auto [kr, kb] = v.at({k.x + 0.5 * r.kenzan.size_m.x, k.y + 0.5 * r.kenzan.size_m.y, 0});
        cairo_rectangle(cr, kl, kb, kr - kl, kf - kb);
        cairo_fill(cr);
    }
    draw_stems(cr, v, r, r.model, true);
    draw_stems(cr, v, r, r.session.result.arrangement, false);
}

std::string criterion_words(const Criterion& c) {
    static const std::map<std::string, std::string> names{{"length_mm", "length"}, {"tilt_deg", "tilt"}, {"azimuth_deg", "direction"}, {"region_mm", "place"}, {"match", "match"}};
    const auto it = names.find(c.name);
    return it == names.end() ? c.name : it->second;
}

// Each main stem's criteria as bars with their points and tips, then the rules.
void draw_criteria(cairo_t* cr, double x, double y, double w, const SessionReport& r) {
    const FormScore& f = r.session.result;
    std::string stem;
    for (const auto& c : f.criteria) {
        if (c.stem != stem) {
            stem = c.stem;
            colour(cr, stem_colour(r.lesson, stem));
            y += 6.0;
            page_text(cr, x, y + 12.0, stem, 13.0, true);
            y += 18.0;
        }
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        page_text(cr, x, y + 10.0, criterion_words(c), 11.0);
        const double bar_x = x + 70.0, bar_w = 120.0;
        const double share = c.max_points > 0.0 ? std::clamp(c.points / c.max_points, 0.0, 1.0) : 0.0;
        cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
        cairo_rectangle(cr, bar_x, y + 1.0, bar_w, 11.0);
        cairo_fill(cr);
        if (share >= 0.999) cairo_set_source_rgb(cr, 0.2, 0.6, 0.3);
        else if (share >= 0.3) cairo_set_source_rgb(cr, 0.9, 0.6, 0.1);
        else cairo_set_source_rgb(cr, 0.8, 0.2, 0.15);
        cairo_rectangle(cr, bar_x, y + 1.0, bar_w * share, 11.0);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        char points[32];
        std::snprintf(points, sizeof points, "%.1f / %.0f", c.points, c.max_points);
        page_text(cr, bar_x + bar_w + 6.0, y + 10.0, points, 10.0);
        y += 15.0;
        if (share < 0.999) {
            cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
            y = wrapped(cr, x + 10.0, y + 9.0, c.tip, 9.5, w - 10.0) - 6.0;
        }
    }
    y += 10.0;
    for (const auto& rule : f.rules) {
        if (rule.ok) cairo_set_source_rgb(cr, 0.2, 0.55, 0.3);
        else cairo_set_source_rgb(cr, 0.8, 0.2, 0.15);
        page_text(cr, x, y + 10.0, rule.ok ? "met" : "not met", 10.0, true);
        cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
        y = wrapped(cr, x + 52.0, y + 10.0, rule.tip, 9.5, w - 52.0) - 8.0;
        y += 6.0;
    }
}

// Score by session, this one ringed, each point its date and score.
void draw_trend(cairo_t* cr, double x0, double y0, double w, double h, const SessionReport& r) {
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    page_text(cr, x0, y0 + 14.0, "the trend in this lesson", 12.0, true);
    if (!r.in_database) {
        wrapped(cr, x0, y0 + 34.0, "not in the progress database: no trend", 11.0, w);
        return;
    }
    const auto& t = r.trend;
    const double top = y0 + 34.0, bottom = y0 + h - 30.0, left = x0 + 30.0, right = x0 + w - 30.0;
    cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
    cairo_set_line_width(cr, 1.0);
    for (const double s : {0.0, 50.0, 100.0}) {
        const double y = bottom - s / 100.0 * (bottom - top);
        cairo_move_to(cr, left, y);
        cairo_line_to(cr, right, y);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.5, 0.5, 0.5);
        page_text(cr, left - 6.0, y + 4.0, std::to_string(static_cast<int>(s)), 9.0, false, 1.0);
        cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
    }
    const auto x_of = [&](std::size_t i) { return t.size() == 1 ? 0.5 * (left + right) : left + (right - left) * static_cast<double>(i) / static_cast<double>(t.size() - 1); };
    const auto y_of = [&](double s) { return bottom - std::clamp(s, 0.0, 100.0) / 100.0 * (bottom - top); };
    cairo_set_source_rgb(cr, 0.2, 0.35, 0.7);
    cairo_set_line_width(cr, 2.0);
    for (std::size_t i = 0; i < t.size(); ++i) (i ? cairo_line_to : cairo_move_to)(cr, x_of(i), y_of(t[i].result.score));
    cairo_stroke(cr);
    // Every label when they fit; otherwise the first, the last and this one.
    const bool all = t.size() <= 8;
    for (std::size_t i = 0; i < t.size(); ++i) {
        const bool here = t[i].id == r.session.id;
        cairo_set_source_rgb(cr, 0.2, 0.35, 0.7);
        cairo_new_path(cr);
        cairo_arc(cr, x_of(i), y_of(t[i].result.score), here ? 6.0 : 3.5, 0.0, 2.0 * 3.14159265358979323846);
        cairo_fill(cr);
        if (all || here || i == 0 || i + 1 == t.size()) {
            cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
            char label[64];
            std::snprintf(label, sizeof label, "%.0f", t[i].result.score);
            page_text(cr, x_of(i), y_of(t[i].result.score) - 9.0, label, 10.0, here, 0.5);
            const std::string when = date_of(t[i].started_unix_s);
            if (when.size() >= 16) page_text(cr, x_of(i), bottom + 16.0, when.substr(5, 11), 8.5, false, 0.5);
        }
    }
}

void draw_page(cairo_t* cr, const SessionReport& r) {
    cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
    cairo_paint(cr);
    const SessionRecord& s = r.session;
    cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
    page_text(cr, 30.0, 40.0, r.lesson.school + ": " + r.lesson.title, 20.0, true);
    std::string who = (s.trainee.empty() ? "a trainee" : s.trainee) + (s.kind == "demonstration" ? " (a demonstration)" : "");
    if (const std::string when = date_of(s.started_unix_s); !when.empty()) who += ", " + when + " UTC";
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    page_text(cr, 30.0, 62.0, who, 12.0);
    if (!r.replay_check.empty()) {
        // Whether what the page shows is what the recording replays to.
        if (r.checked && r.replays) cairo_set_source_rgb(cr, 0.2, 0.55, 0.3);
        else cairo_set_source_rgb(cr, 0.8, 0.2, 0.15);
        page_text(cr, 30.0, 76.0, r.replay_check, 10.0);
    }
    char score[32];
    std::snprintf(score, sizeof score, "%.1f / 100", s.result.score);
    cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
    page_text(cr, page_w - 30.0, 46.0, score, 28.0, true, 1.0);
    draw_view(cr, View{30.0, 80.0, 340.0, 400.0, true}, r);
    draw_view(cr, View{380.0, 80.0, 340.0, 400.0, false}, r);
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    page_text(cr, 30.0, 498.0, "solid: the arrangement as scored (dotted: fallen); dashed: the form's model; grey: supporting stems", 10.0);
    draw_trend(cr, 30.0, 510.0, 690.0, 270.0, r);
    draw_criteria(cr, 740.0, 80.0, 360.0, r);
}


// The session's lesson, its kenzan and its model arrangement.
Result<void> with_lesson(SessionReport& r) {
    auto lesson = load_lesson(r.session.lesson);
    // A lesson given as a file travels with its recording (lesson.json beside session.json).
    if (!lesson && !r.session.recording.empty()) {
        std::error_code ec;
        const auto copy = std::filesystem::path(r.session.recording) / "lesson.json";
        if (std::filesystem::is_regular_file(copy, ec)) lesson = load_lesson(copy.string());
    }
    if (!lesson) return make_error(lesson.error().code, "its lesson: " + lesson.error().message);
    r.lesson = std::move(lesson).value();
    auto kenzan = footprint_of(r.lesson);
    if (!kenzan) return std::move(kenzan).error();
    r.kenzan = *kenzan;
    r.model = model_arrangement(r.lesson, r.kenzan);
    return {};
}

} // namespace

Result<SessionReport> load_session_report(const std::filesystem::path& recording, const std::filesystem::path& db) {
    std::error_code ec;
    const bool recorded = std::filesystem::is_regular_file(recording / "session.json", ec);
    SessionReport r;
    if (auto progress = ProgressDb::open_read_only(db)) {
        auto sessions = progress->sessions();
        if (!sessions) return std::move(sessions).error();
        const auto found = std::find_if(sessions->begin(), sessions->end(), [&](const SessionRecord& s) {
            return !s.recording.empty() && (same_folder(s.recording, recording) ||
                                            (!recorded && std::filesystem::path(s.recording).lexically_normal() == std::filesystem::absolute(recording, ec).lexically_normal()));
        });
        if (found != sessions->end()) {
            r.session = *found;
            r.in_database = true;
            for (const auto& s : *sessions) {
                if (s.trainee == found->trainee && s.lesson == found->lesson && s.started_unix_s <= found->started_unix_s) r.trend.push_back(s);
            }
        }
    } else if (progress.error().code != ErrorCode::not_found) {
        return std::move(progress).error();
    }
    if (!recorded) {
        // The folder is gone, but the database holds everything the page shows: reported, unchecked.
        if (!r.in_database) return make_error(ErrorCode::not_found, recording.string() + ": not a session's recording (no session.json in it)");
        r.replay_check = "not checked against its recording: " + recording.string() + " is gone";
        if (auto done = with_lesson(r); !done) return make_error(done.error().code, recording.string() + ": " + done.error().message);
        return r;
    }
    // The recording replayed, as `replay --json` does: what the page shows is what it replays to, or the
    // page says it is not (a recording edited by hand, another lesson swapped in).
    auto replayed = replay_lesson_session(recording);
    if (!replayed) {
        if (!r.in_database) return make_error(replayed.error().code, recording.string() + ": " + replayed.error().message);
        r.replay_check = "not checked: the recording does not replay (" + replayed.error().message + ")";
    } else {
        r.checked = true;
        const bool same_hash = replayed->state_hash == replayed->recorded_state_hash;
        const bool same_score = std::abs(replayed->score.score - replayed->recorded_score) < 1e-6;
        const bool as_stored = !r.in_database || std::abs(replayed->score.score - r.session.result.score) < 0.05;
        r.replays = same_hash && same_score && as_stored;
        char words[200];
        if (r.replays) {
            std::snprintf(words, sizeof words, "checked: its recording replays to this result (%.1f, the same final state)", replayed->score.score);
        } else {
            std::snprintf(words, sizeof words, "NOT what its recording replays to: %.1f against %.1f stored%s", replayed->score.score,
                          r.in_database ? r.session.result.score : replayed->recorded_score, same_hash ? "" : ", another final state");
        }
        r.replay_check = words;
        if (!r.in_database) {
            r.session.lesson = replayed->score.lesson;
            r.session.kind = replayed->kind;
            r.session.result = std::move(replayed->score);
        }
    }
    if (!r.in_database) r.session.recording = recording.string();
    if (auto done = with_lesson(r); !done) return make_error(done.error().code, recording.string() + ": " + done.error().message);
    return r;
}

Result<SessionReport> session_report_for(SessionRecord session, const ProgressDb* db) {
    SessionReport r;
    r.session = std::move(session);
    if (db) {
        auto sessions = db->sessions({r.session.trainee, r.session.lesson});
        if (!sessions) return std::move(sessions).error();
        r.in_database = true;
        for (auto& s : *sessions) {
            if (s.id != r.session.id && s.started_unix_s <= r.session.started_unix_s) r.trend.push_back(std::move(s));
        }
        r.trend.push_back(r.session); // as it stands now, stored or not yet
    }
    if (auto done = with_lesson(r); !done) return done.error();
    return r;
}

Result<std::string> render_session_report(const SessionReport& report, ReportFormat format) {
    // The PDF in points: the same page at 0.75 (A4 landscape, 842 x 595 pt).
    return draw_cairo_page(format == ReportFormat::pdf ? PlotFormat::pdf : PlotFormat::png, page_w, page_h, 0.75,
                           [&](cairo_t* cr) { draw_page(cr, report); });
}

Result<void> write_session_report(const SessionReport& report, const std::filesystem::path& dir) {
    assets::OutputBatch out;
    if (auto made = out.folder(dir); !made) return made;
    for (const auto& [name, format] : {std::pair{"report.png", ReportFormat::png}, std::pair{"report.pdf", ReportFormat::pdf}}) {
        auto bytes = render_session_report(report, format);
        if (!bytes) return bytes.error();
        if (auto added = out.add(dir / name, *bytes); !added) return added;
    }
    return out.commit();
}

} // namespace ikebana::game
