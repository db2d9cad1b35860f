#pragma once
// A lesson on the table: the scene it opens (its container with the kenzan in it, the materials lying
// in front, the hands beside them, the camera back far enough for the form's height), and the
// arrangement measured from what the simulation shows, in the lesson's terms (kenzan coordinates,
// length above the pins, tilt and direction from where each stem enters them).
#include "components/snapshot.hpp"
#include "engine/core/result.hpp"
#include "game/lesson/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "game/scene/scene.hpp"

namespace ikebana::game {

// A form lesson's scene; a sample lesson's is its scene file. The kenzan's centre is at the origin.
Result<SceneDef> scene_for_lesson(const LessonDef& lesson);

// The kenzan's footprint as the scoring needs it, from its layout.
Result<KenzanFootprint> footprint_of(const LessonDef& lesson);

// The stems in (or fallen from) the kenzan, none held by a hand: materials still on the table are not
// part of the arrangement. Roles are left to the scoring.
Arrangement measure_arrangement(const components::FrameSnapshot& frame);

} // namespace ikebana::game
