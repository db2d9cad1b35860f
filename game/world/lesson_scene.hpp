#pragma once
// A lesson on the table: the scene it opens (its container with the kenzan in it, the materials lying
// in front, the hands beside them, the camera back far enough for the form's height), and the
// arrangement measured from what the simulation shows, in the lesson's terms (kenzan coordinates,
// length above the pins, tilt and direction from where each stem enters them).
#include <map>
#include <optional>
#include "components/snapshot.hpp"
#include "engine/core/result.hpp"
#include "game/training/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "game/scene/scene.hpp"
#include "game/species/species.hpp"

namespace ikebana::game {

// A form lesson's scene; a sample lesson's is its scene file. The kenzan's centre is at the origin.
Result<SceneDef> scene_for_lesson(const LessonDef& lesson);

// The kenzan's footprint as the scoring needs it, from its layout.
Result<KenzanFootprint> footprint_of(const LessonDef& lesson);

// Where a stem's bottom goes for it to enter the pins' tops at `base` (where the form, and the score,
// put a stem: measure_arrangement measures from there), held along `want` with `in_pins` of it in the
// pins. Set at the base itself, a stem at 70 degrees with 13 mm in the pins entered 36 mm further out,
// toward the wall.
[[nodiscard]] glm::dvec2 bottom_for(glm::dvec2 base, glm::dvec3 want, double in_pins);

// The largest tilt at which a straight stem from `bottom` leaning toward `azimuth` passes over the
// container's wall, a radius and 2 mm above its rim where it crosses the wall's middle; none if it ends
// before the wall (`reach_m`: its length from the bottom) or the container is a vase (the stems rise
// from its mouth).
[[nodiscard]] std::optional<double> rim_tilt_rad(const components::Container& c, glm::dvec3 bottom, double azimuth_rad, double reach_m, double radius_m);
// How far inside rim_tilt_rad a low stem is aimed (by the demonstration, and in the trainee's next step).
inline constexpr double rim_margin_rad = 1.0 * 3.14159265358979323846 / 180.0;
// The lean a model stem is to be set at when the container's rim would not let it lean as far as its
// form (rim_margin_rad inside the steepest that clears the rim from where the form puts it, in the
// frame's kenzan and container); nothing when the form's lean clears it, or for a stem that rises
// upright from the pins first (a two-point path).
[[nodiscard]] std::optional<double> rim_held_tilt_rad(const ArrangementStem& stem, const components::FrameSnapshot& frame, double radius_m);

// The stems in (or fallen from) the kenzan, none held by a hand: materials still on the table are not
// part of the arrangement. Roles are left to the scoring.
Arrangement measure_arrangement(const components::FrameSnapshot& frame);

} // namespace ikebana::game

namespace ikebana::game {

// What the trainee is told about the stem a hand holds: which role it is heading for (the first of the
// form's roles its species may play that no standing stem plays yet), the length to cut it to for that
// role (its length above the kenzan plus what the pins hold), and its tilt and direction now against
// the role's; and, held far from its bottom end, to take it again near that end.
struct HeldStemAdvice {
    std::string role;
    double keep_length_m = 0.0; // cut to this (0: no role left for it)
    std::vector<std::string> lines;
    std::string next_step; // the one thing to do now, in a short line (empty: no role left for it)
    // Held in the pins at a lean they cannot hold once let go: what to say of it (empty: they hold it).
    std::string would_sink;
    // The held stem's lean now against its role's band (lesson convention: azimuth 0 toward the viewer,
    // + to the viewer's left), for the panel's gauge. None without a role for it.
    struct Gauge {
        double tilt_rad = 0.0, azimuth_rad = 0.0;
        double target_tilt_rad = 0.0, tilt_tolerance_rad = 0.0;
        std::optional<double> target_azimuth_rad;
        double azimuth_tolerance_rad = 0.0;
        std::size_t role = 0; // its place in the lesson's stems (role_colour)
    };
    std::optional<Gauge> gauge;
};
HeldStemAdvice advise_held_stem(const LessonDef& lesson, const KenzanFootprint& kenzan, const components::FrameSnapshot& frame, std::size_t hand);

// The role a stem of this species would be heading for now (as advise_held_stem picks it): a main
// role's name, "a supporting stem (jushi)" where the form has them and no main role is left for it,
// or empty: none.
[[nodiscard]] std::string role_heading_for(const LessonDef& lesson, const KenzanFootprint& kenzan, const components::FrameSnapshot& frame,
                                           const std::string& species);

// A press of this hand on a stem lying out of the kenzan, far from its bottom end (where it could not be
// pushed into the pins from), or on the part of it below `along_m` (what C would cut off): the point
// `along_m` up from that end where the hand takes it instead (the mouse's hand goes there). Nothing when
// the press would take it there already, or takes nothing.
// `along_m`: how far up from its end (60 mm by default, grip_along_m for a lesson's role).
[[nodiscard]] std::optional<glm::dvec3> bottom_grip_for(const components::FrameSnapshot& frame, std::size_t hand, double along_m = 0.06);

// Where up from its end a press should take the stem this hand would take, for a lesson: 60 mm, or
// 30 mm above what C would cut off for the role it is heading for (taken by its end and cut for a
// 59 mm jushi, the hand held the piece that came off).
[[nodiscard]] double grip_along_m(const LessonDef& lesson, const KenzanFootprint& kenzan, const components::FrameSnapshot& frame, std::size_t hand);

} // namespace ikebana::game

#include "engine/render/draw_list.hpp"
#include "engine/render/text_overlay.hpp"

namespace ikebana::game {

// The form's targets over the kenzan, translucent: each main stem of the model arrangement at its
// nominal length, tilt and direction from its place, in its role's colour (ghost_colour_name).
// With a frame that has the container, a low stem is drawn at the lean its rim allows
// (rim_held_tilt_rad: the lean the panel asks for), not through the container's wall.
void add_form_ghosts(render::DrawList& list, const LessonDef& lesson, const KenzanFootprint& kenzan, const glm::dvec3& kenzan_origin_m,
                     const components::FrameSnapshot* frame = nullptr);
[[nodiscard]] std::string ghost_colour_name(std::size_t role);
// The form's model arrangement as the flowers themselves, on a plate at `plate_origin_m` (behind the
// container): stems along the model's lines, heads, petals and leaves as the species have them, and
// over each tip a marker in its role's colour (the HUD's legend names the colours). What a teacher
// sets beside a trainee's work. Species missing from `species` are left out.
void add_model_flowers(render::DrawList& list, const LessonDef& lesson, const KenzanFootprint& kenzan, const glm::dvec3& plate_origin_m,
                       const std::map<std::string, SpeciesDef>& species);
// Their names, on the world (each eye sees a label at the depth of what it names): over each role's
// tip in the model by the container, its label ("Shin"); over each ghost's end, the role with its
// target length and tilt ("shin 630 mm, 15°"). Both in the role's colour.
[[nodiscard]] std::vector<render::OverlayPanel> form_labels(const LessonDef& lesson, const KenzanFootprint& kenzan, const glm::dvec3& kenzan_origin_m,
                                                           const glm::dvec3& plate_origin_m, const components::FrameSnapshot* frame = nullptr);
// Where that plate goes: behind the container and right, at the kenzan's height.
[[nodiscard]] glm::dvec3 model_plate_origin(const LessonDef& lesson, const glm::dvec3& kenzan_origin_m);

} // namespace ikebana::game
