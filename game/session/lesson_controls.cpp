#include "game/session/lesson_controls.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <utility>

#include "components/insertion.hpp"
#include "game/world/lesson_scene.hpp"
#include "systems/haptics/trainee_command_system.hpp"
#include "systems/physics/part_attachment.hpp"
#include "systems/presentation/draw_list.hpp"

namespace ikebana::game {

std::string prune_preview(const components::FrameSnapshot& frame, std::uint8_t hand) {
    const auto& h = frame.hands[hand & 1u];
    if (!h.present) return "";
    const glm::dvec3 at = h.position_m;
    const double reach = 0.5 * h.edge_m;
    double best = std::numeric_limits<double>::infinity(); // nearer than what was found, and within reach
    std::string what;
    const auto to_segment = [](glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
        const glm::dvec3 ab = b - a;
        const double len2 = glm::dot(ab, ab);
        const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
        return glm::length(p - (a + t * ab));
    };
    const auto consider_parts = [&](const std::vector<glm::dvec3>& x, const std::vector<glm::dvec3>& directors, const std::vector<components::Part>& parts,
                                    const std::string& species) {
        for (const auto& part : parts) {
            if (part.kind == components::PartKind::stem || part.mesh.empty() || x.empty()) continue;
            const auto f = systems::physics::attachment_frame(x, std::min<std::size_t>(part.stem_point, x.size() - 1), directors);
            const double d = glm::length(f.place(part.offset_m) - at);
            if (d <= reach && d < best) {
                best = d;
                what = std::string("P here: strips a ") + (part.kind == components::PartKind::leaf ? "leaf" : "blossom") + " of the " + species;
            }
        }
    };
    for (const auto& flower : frame.flowers) {
        std::string species = flower.species;
        std::replace(species.begin(), species.end(), '_', ' ');
        for (const auto& twig : flower.twigs) {
            for (std::size_t i = 1; i < twig.points_m.size(); ++i) {
                const double d = std::max(0.0, to_segment(at, twig.points_m[i - 1], twig.points_m[i]) - 0.5 * twig.diameter_m);
                if (d <= reach && d < best) {
                    best = d;
                    what = "P here: cuts off a twig of the " + species + " at its fork";
                }
            }
            consider_parts(twig.points_m, twig.directors, twig.parts, species);
        }
        consider_parts(flower.points_m, flower.directors, flower.parts, species);
    }
    return what;
}

std::string ascii_for_hud(std::string text) {
    for (const auto& [from, to] : {std::pair<std::string, std::string>{"°", " deg"}, {"±", "+-"}, {"×", "x"}}) {
        for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
    }
    return text;
}

std::vector<std::string> wrap_words(const std::string& text, std::size_t width) {
    std::vector<std::string> lines;
    std::string line, word;
    const auto flush_word = [&] {
        if (word.empty()) return;
        if (!line.empty() && line.size() + 1 + word.size() > width) {
            lines.push_back(line);
            line = "  ";
        }
        line += (line.empty() || line == "  " ? "" : " ") + word;
        word.clear();
    };
    for (const char ch : text) {
        if (ch == ' ') flush_word();
        else word += ch;
    }
    flush_word();
    if (!line.empty()) lines.push_back(line);
    return lines;
}

std::vector<std::string> hud_lines_of(const std::string& text) { return wrap_words(ascii_for_hud(text), 56); }

devices::MouseKeyboardHands::Config lesson_mouse_config() {
    devices::MouseKeyboardHands::Config c;
    c.workspace_width_m = 0.7;
    c.workspace_height_m = 0.6;
    c.reach_min_m = {-0.45, -0.5, 0.0};
    c.reach_max_m = {0.45, 0.4, 0.6};
    // 20 mm a wheel notch: from the materials' row to the kenzan was 13 notches at 10 mm, and a
    // first-time trainee found the wheel slow (the hand stays under the cursor, so the view shows
    // little of it: the foot mark on the table does).
    c.depth_per_scroll_m = 0.02;
    return c;
}

std::string role_target_words(const LessonDef& l, std::size_t i) {
    if (i >= l.stems.size()) return "";
    const auto& m = l.stems[i];
    constexpr double deg = 180.0 / 3.14159265358979323846;
    char text[200];
    std::string follows;
    if (m.length_of.kind == LengthBase::Kind::role) {
        std::snprintf(text, sizeof text, " (%.2g × %s as you cut it)", m.length_ratio.target, l.stems[m.length_of.role].role.c_str());
        follows = text;
    }
    std::snprintf(text, sizeof text, "%.0f mm above the kenzan%s, %.0f° ±%.0f° %s, in %s", nominal_length_m(l, i) * 1e3, follows.c_str(), m.tilt_rad.target * deg,
                  m.tilt_rad.tolerance * deg, m.azimuth_rad ? ("toward the " + direction_words(m.azimuth_rad->target)).c_str() : "to any side",
                  region_words(m.region).c_str());
    return text;
}

std::string species_words(std::string id) {
    std::replace(id.begin(), id.end(), '_', ' ');
    return id;
}

std::string LessonControls::reach_words(const components::FrameSnapshot& latest, std::uint8_t hand) const {
    const auto& h = latest.hands[hand & 1u];
    const auto reach = systems::stem_in_reach(latest, hand);
    // What stands already, and a stem that fell: said first.
    std::string before;
    const auto placed = score_form(lesson_, measure_arrangement(latest), footprint_);
    std::vector<std::string> standing;
    if (placed) {
        for (const auto& s : placed->arrangement.stems) {
            if (s.standing && s.role != "supporting") standing.push_back(s.role);
        }
    }
    for (const auto& f : latest.flowers) {
        if (f.fallen) {
            before = "the " + species_words(f.species) + " fell (" + components::fall_words(f.fall_reason) + "); ";
            break;
        }
    }
    if (before.empty() && !standing.empty()) {
        for (std::size_t i = 0; i < standing.size(); ++i) before += (i ? ", " : "") + standing[i];
        before += standing.size() == 1 ? " stands; " : " stand; ";
    }
    if (!reach) {
        if (!h.grab_button && placed && standing.size() >= lesson_.stems.size()) {
            // A rule still unmet is the next thing to do (a trainee read "every role stands" and never
            // added the jushi that hide the kenzan, which the score then asked for).
            for (const auto& r : placed->rules) {
                if (!r.ok) return before + "to do: " + r.tip + "; or Score (Enter)";
            }
            return before + "every role stands: Score (Enter)";
        }
        // A press that took nothing says why.
        if (h.grab_button) {
            const auto& other = latest.hands[(hand + 1u) & 1u];
            for (std::size_t f = 0; f < latest.flowers.size(); ++f) {
                for (const auto& p : latest.flowers[f].points_m) {
                    if (other.held_flower == static_cast<std::int32_t>(f) && glm::length(p - h.position_m) < 2.0 * h.edge_m)
                        return "the other hand holds that stem: Tab to it, and let go there first";
                }
            }
            return "nothing under the cube: release the button, point at a stem until it turns yellow, then hold it";
        }
        return before + "take a stem: point at one (the cube goes onto it and it turns yellow) and hold the left button";
    }
    const auto& f = latest.flowers[reach->flower];
    // A stem standing in the pins already plays its role there: that is said, not a role it would
    // head for (hovering over a standing hikae, a trainee read "take the chrysanthemum for a
    // supporting stem").
    std::string plays;
    const bool in_a_hand = static_cast<std::int32_t>(reach->flower) == h.held_flower ||
                           static_cast<std::int32_t>(reach->flower) == latest.hands[(hand + 1u) & 1u].held_flower;
    if (f.in_kenzan && placed && !in_a_hand) { // (a held stem is not measured: the index would be another's)
        std::size_t n = 0; // its place among the measured stems (measure_arrangement's order)
        const auto& other = latest.hands[(hand + 1u) & 1u];
        for (std::size_t i = 0; i < reach->flower; ++i) {
            const auto& g = latest.flowers[i];
            const bool held = static_cast<std::int32_t>(i) == h.held_flower || static_cast<std::int32_t>(i) == other.held_flower;
            if (!held && (g.in_kenzan || g.fallen) && g.points_m.size() >= 2) ++n;
        }
        if (n < placed->arrangement.stems.size()) plays = placed->arrangement.stems[n].role;
    }
    const std::string role = plays.empty() ? role_heading_for(lesson_, footprint_, latest, f.species) : std::string{};
    std::string words = before + "hold the left button to take the " + species_words(f.species) +
                        (!plays.empty() ? " (it stands as " + (plays == "supporting" ? std::string("a supporting stem") : plays) + ")"
                         : role.empty() ? " (no role of the form is left for it)" : " for " + role);
    if (const double along = grip_along_m(latest, hand); bottom_grip_for(latest, hand, along))
    {
        char text[120];
        std::snprintf(text, sizeof text, ": the hand takes it %.0f mm up from its bottom end, above what C cuts off", along * 1e3);
        words += along > 0.1 ? std::string(text) : std::string(": the hand takes it by its bottom end");
    }
    else if (f.in_kenzan) words += ": it comes out of the pins";
    return words;
}

namespace {
// A stem's lean from the vertical, bottom to tip.
double chord_tilt_rad(const components::FlowerStatus& f) {
    if (f.points_m.size() < 2) return 0.0;
    const glm::dvec3 chord = f.points_m.back() - f.points_m.front();
    const double c = glm::length(chord);
    return c > 0.0 ? std::acos(std::clamp(chord.z / c, -1.0, 1.0)) : 0.0;
}
// Sunk further than this past its lean when let go, a stem is said to have sunk.
constexpr double sank_beyond_rad = 6.0 * 3.14159265358979323846 / 180.0;
// Less of the pins' height than this holds a stem too loosely to let go of it.
constexpr double shallow_fraction = 0.6;

// Whether a point is over the container (over the kenzan, where there is none).
bool over_container(const components::FrameSnapshot& latest, glm::dvec3 p) {
    if (latest.container) return latest.container->holds_xy(glm::dvec2(p));
    return latest.kenzan && glm::length(glm::dvec2(p - latest.kenzan->origin_m)) < 0.1;
}
} // namespace

void LessonControls::watch_sinking(const components::FrameSnapshot& latest, const components::HandStatus& h, const std::string& role) {
    constexpr double deg = 180.0 / 3.14159265358979323846;
    const auto flower_at = [&](std::int32_t i) -> const components::FlowerStatus* {
        return i >= 0 && static_cast<std::size_t>(i) < latest.flowers.size() ? &latest.flowers[static_cast<std::size_t>(i)] : nullptr;
    };
    if (h.holding) {
        if (const auto* f = flower_at(h.held_flower)) held_ = {h.held_flower, role, chord_tilt_rad(*f), 0};
        let_go_ = {};
        sank_.clear();
        return;
    }
    // Not let go: Tab handed the mouse to the other hand, which still holds nothing, while this stem
    // stays in the hand that held it.
    const bool still_held = std::any_of(std::begin(latest.hands), std::end(latest.hands),
                                        [&](const components::HandStatus& other) { return other.holding && other.held_flower == held_.flower; });
    if (held_.flower >= 0 && still_held) return;
    if (held_.flower >= 0) {
        // Just let go: watched for about three seconds of readings, if it stays in the pins.
        if (const auto* f = flower_at(held_.flower); f && f->in_kenzan) {
            let_go_ = held_;
            let_go_.readings_left = 90;
        } else if (f && !f->points_m.empty() && over_container(latest, f->points_m.front())) {
            // Let go over the container but not in the pins (a lean had levered it out of them): it
            // falls, and with no stem in the kenzan nothing said so.
            const std::string who = held_.role.empty() ? "the " + species_words(f->species) : held_.role;
            sank_ = who + " was not in the pins when you let go, and fell: take it again, push it down into the pins, then let go";
        }
        held_ = {};
    }
    if (let_go_.readings_left <= 0) return;
    --let_go_.readings_left;
    const auto* f = flower_at(let_go_.flower);
    if (!f || !f->in_kenzan || f->fallen) {
        let_go_ = {};
        return;
    }
    const double now = chord_tilt_rad(*f);
    if (now - let_go_.tilt_rad <= sank_beyond_rad) return;
    // Still within its role's band, it is where the form wants it: nothing to take again for (a
    // trainee's shin sank from 15 to 22 degrees, in its 15 +-10, and was told to take it again).
    const auto form = std::find_if(lesson_.stems.begin(), lesson_.stems.end(), [&](const MainStemDef& m) { return m.role == let_go_.role; });
    if (form != lesson_.stems.end() && std::abs(now - form->tilt_rad.target) <= form->tilt_rad.tolerance) return;
    char text[260];
    const std::string who = let_go_.role.empty() ? "the " + species_words(f->species) : let_go_.role;
    // As deep as the pins go, pushing deeper is no help.
    const bool full_depth = latest.kenzan && f->depth_m >= 0.9 * latest.kenzan->pin_height_m();
    std::snprintf(text, sizeof text, "%s sank from %.0f° to %.0f° once let go (%.0f mm deep in the pins): take it again and %s %.0f° steeper than you want it",
                  who.c_str(), let_go_.tilt_rad * deg, now * deg, f->depth_m * 1e3, full_depth ? "set it" : "push it deeper, or set it",
                  (now - let_go_.tilt_rad) * deg);
    sank_ = text;
}

LessonControls::Effects LessonControls::update(const platform::PointerState& in, std::uint8_t hand, const components::FrameSnapshot& latest,
                                               systems::TraineeChannel& trainee) {
    Effects effects;
    lines_.clear();
    const auto say = [&](const std::string& text) {
        for (auto& line : hud_lines_of(text)) lines_.push_back(std::move(line));
    };
    say(lesson_.school + ": " + lesson_.title);
    say(std::string("Mouse: ") + (hand ? "right" : "left") + " hand (Tab: other). Left button: hold. Shift or wheel: depth. Ctrl+drag: tilt. Ctrl+Shift+drag: twist. "
                                                         "C: cut for its role. P: prune at the cube. G: targets. R: start again. Enter: score.");
    const bool form = lesson_.scoring == "form";
    HeldStemAdvice advice;
    if (form) advice = advise_held_stem(lesson_, footprint_, latest, hand);
    for (const auto& line : advice.lines) say("> " + line);
    advice_ = advice.lines;
    gauge_ = advice.gauge;
    next_step_ = form ? advice.next_step : "copy the sample arrangement, then Score (Enter)";
    const auto& h = latest.hands[hand & 1u];
    if (h.holding) scored_ = false;
    watch_sinking(latest, h, advice.role);
    const bool held_in_pins = h.holding && h.held_flower >= 0 && static_cast<std::size_t>(h.held_flower) < latest.flowers.size() &&
                              latest.flowers[static_cast<std::size_t>(h.held_flower)].in_kenzan;
    if (form && held_in_pins) {
        char text[320];
        const double depth_m = latest.flowers[static_cast<std::size_t>(h.held_flower)].depth_m;
        // Shallow (a lean in the pins can lever it up), it would sink or fall once let go.
        if (latest.kenzan && depth_m < shallow_fraction * latest.kenzan->pin_height_m())
            std::snprintf(text, sizeof text, "it is only %.0f mm deep in the pins (they are %.0f mm tall): push it down (move the mouse down) before you let go",
                          depth_m * 1e3, latest.kenzan->pin_height_m() * 1e3);
        else if (!advice.would_sink.empty())
            std::snprintf(text, sizeof text, "%s", advice.would_sink.c_str());
        else
            std::snprintf(text, sizeof text, "it is in the pins, %.0f mm deep: release the button to let go of it (click, if the button is up)", depth_m * 1e3);
        next_step_ = text;
    } else if (form && h.holding) {
        // Where it would go in, if that is wrong: said before anything else.
        if (const auto mark = systems::entry_mark(latest, hand); mark && !mark->good() && advice.keep_length_m > 0.0)
        {
            char text[200];
            std::snprintf(text, sizeof text,
                          "lean it %.0f° less here (it would go through the container's wall, or rest on its rim), or move it toward the container's middle",
                          std::max(1.0, std::ceil((mark->lower_tilt_rad - mark->rim_tilt_rad) * 180.0 / 3.14159265358979323846)));
            next_step_ = mark->meets_wall ? std::string(text) : "move it over the kenzan: the red ring shows it would miss the pins";
        }
        if (next_step_.empty()) next_step_ = "no role is left for this stem: let go of it (release the button) away from the kenzan";
        // The hand held back from where the mouse puts it, sideways: only the container's wall does
        // that (the table and the kenzan's plate stop it going down).
        const auto* held = h.held_flower >= 0 && static_cast<std::size_t>(h.held_flower) < latest.flowers.size() ? &latest.flowers[static_cast<std::size_t>(h.held_flower)] : nullptr;
        const bool low = held && latest.container &&
                         std::any_of(held->points_m.begin(), held->points_m.end(), [&](const glm::dvec3& p) { return p.z < latest.container->rim_z_m; });
        if (low && glm::length(glm::dvec2(h.device_m - h.position_m)) > 0.015)
            next_step_ = "the container's wall is in the way: lift it over the rim (move the mouse up), then move it in";
    } else if (form) {
        next_step_ = reach_words(latest, hand);
        if (!sank_.empty()) next_step_ = sank_;
    }
    // Where along the held stem the hand holds it, from its bottom end: a cut below the hand keeps the
    // part in the hand. Cut above it, the hand held the piece that came off, and the flower hung 120 mm
    // from the cube (a trainee took a chrysanthemum by its bottom end and cut it for a 59 mm jushi).
    double grip_from_bottom_m = 0.0, held_length_m = 0.0;
    if (h.holding && h.held_flower >= 0 && static_cast<std::size_t>(h.held_flower) < latest.flowers.size()) {
        const auto& x = latest.flowers[static_cast<std::size_t>(h.held_flower)].points_m;
        std::size_t nearest = 0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            if (glm::length(x[i] - h.position_m) < glm::length(x[nearest] - h.position_m)) nearest = i;
            if (i > 0) held_length_m += glm::length(x[i] - x[i - 1]);
            if (i > 0 && i <= nearest) grip_from_bottom_m = held_length_m;
        }
    }
    const bool grip_cut_away = advice.keep_length_m > 0.0 && held_length_m - advice.keep_length_m > grip_from_bottom_m - 0.01;
    if (in.letter(cut_letter) && !cut_was_down_ && grip_cut_away) cut_refused_for_ = 60; // about two seconds of readings
    if (in.letter(cut_letter) && !cut_was_down_ && advice.keep_length_m > 0.0 && !grip_cut_away &&
        trainee.push({systems::TraineeCommand::Kind::cut, hand, advice.keep_length_m})) {
        effects.cut_for = advice.role;
        effects.cut_to_m = advice.keep_length_m;
    }
    if (cut_refused_for_ > 0 && h.holding) {
        --cut_refused_for_;
        char text[200];
        std::snprintf(text, sizeof text, "C would cut off the part in your hand: let go, and take it again above its lowest %.0f mm (nearer the flower)",
                      (held_length_m - advice.keep_length_m) * 1e3);
        next_step_ = text;
    } else if (!h.holding) {
        cut_refused_for_ = 0;
    }
    cut_was_down_ = in.letter(cut_letter);
    // What P would take, beside the next step (the panel shows that line; the yellow mark is for stems).
    if (const auto preview = prune_preview(latest, hand); !preview.empty() && prune_said_for_ == 0) {
        say(preview);
        next_step_ += (next_step_.empty() ? "" : "; or ") + preview;
    }
    if (in.letter(prune_letter) && !prune_was_down_ && trainee.push({systems::TraineeCommand::Kind::prune, hand, 0.0})) {
        cuttings_before_prune_ = latest.cuttings.size();
        prune_said_for_ = 60; // about two seconds of readings
        pruned_ = false;
    }
    prune_was_down_ = in.letter(prune_letter);
    if (prune_said_for_ > 0) {
        --prune_said_for_;
        pruned_ = pruned_ || latest.cuttings.size() > cuttings_before_prune_;
        // The simulation answers within a few readings; until then nothing is said either way.
        if (pruned_) next_step_ = "pruned: what came off lies on the table (P again for the next twig, leaf or blossom)";
        else if (prune_said_for_ < 50) next_step_ = "nothing to prune under the cube: move it onto a twig, a leaf or a blossom, then P";
    }
    if (in.letter(ghost_letter) && !ghost_was_down_ && form) {
        ghosts_ = !ghosts_;
        effects.ghosts_toggled = true;
    }
    ghost_was_down_ = in.letter(ghost_letter);
    if (ghosts_) {
        std::string legend = "  targets (G):";
        for (std::size_t i = 0; i < lesson_.stems.size(); ++i) legend += " " + lesson_.stems[i].role + " " + ghost_colour_name(i);
        const auto model = model_arrangement(lesson_, footprint_);
        if (std::any_of(model.stems.begin(), model.stems.end(), [](const ArrangementStem& s) { return s.role == "supporting"; }))
            legend += ", supporting (jushi) " + ghost_colour_name(lesson_.stems.size());
        lines_.push_back(legend);
        lines_.push_back("  the model stands behind the container, right; each stem named");
    }
    effects.restart = in.letter(reset_letter) && !reset_was_down_;
    if (effects.restart) {
        let_go_ = {};
        sank_.clear();
    }
    reset_was_down_ = in.letter(reset_letter);
    if (in.finish_key && !enter_was_down_ && form) {
        effects.score = score_form(lesson_, measure_arrangement(latest), footprint_);
        scored_ = true;
    }
    // (Over a stem, what a press would take is said instead.)
    if (form && scored_ && !h.holding && !systems::stem_in_reach(latest, hand))
        next_step_ = "scored: the bars below show each stem; change what you like, or R to start over, Esc for the lessons";
    enter_was_down_ = in.finish_key;
    return effects;
}

} // namespace ikebana::game
