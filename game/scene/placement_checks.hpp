#pragma once
// What a scene may only be checked for once its kenzan and species are known: an inserted stem stands
// on the pins, points up out of them, and has its own place (200 sunflowers in one hole once all
// "stood"; a stem pointing down was "in the kenzan" and fell; one placed far off lay on the table
// without a word). Errors name the scene file and the flower's JSON pointer.
#include <map>
#include <string>

#include "components/kenzan.hpp"
#include "engine/core/result.hpp"
#include "game/scene/scene.hpp"
#include "game/species/species.hpp"

namespace ikebana::game {

// The steepest an inserted stem may lean: 10 degrees above the horizontal, the experiment's lowest angle.
inline constexpr double min_inserted_elevation_deg = 10.0;

Result<void> check_placements(const SceneDef& scene, const components::Kenzan& kenzan, const std::map<std::string, SpeciesDef>& species);

} // namespace ikebana::game
