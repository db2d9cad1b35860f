#pragma once
// What a designer wants to know of a species before it meets a trainee: does it stand in the kenzan
// upright, at 45 and at 70 degrees, and by how much; how far does it sag held horizontally by its
// base. Each trial is a small scene on the deterministic clock (the same world as `sim`), so the
// numbers are the simulator's own, and the same every time.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "components/snapshot.hpp"
#include "engine/core/result.hpp"
#include "game/scene/scene.hpp"

namespace ikebana::game {

struct StandTrial {
    double set_at_deg = 0.0;     // its tilt from the vertical as it was put in the pins
    bool stands = false;         // in the kenzan and not fallen after settling
    std::string reason;          // why it fell ("" when it stands)
    double tilt_deg = 0.0;       // of the line from its bottom to its top, after settling
    double holding_nm = 0.0;     // what the pins can hold
    double gravity_nm = 0.0;     // what its weight asks of them
    [[nodiscard]] double margin() const { return gravity_nm > 0.0 ? holding_nm / gravity_nm : 0.0; }
};

struct SagTrial {
    double tip_drop_mm = 0.0;    // the top below the held base (negative: above it)
    double tip_angle_deg = 0.0;  // of the line from the base to the top, below the horizontal
};

// One trial's scene and its last frame, for a picture of it.
struct TrialScene {
    SceneDef scene;
    components::FrameSnapshot last;
};

struct SpeciesMechanics {
    std::string id;
    double length_mm = 0.0;
    std::vector<StandTrial> stands; // at 0, 45 and 70 degrees
    SagTrial sag;
    std::vector<TrialScene> scenes; // the stand trials', then the sag's
};

inline constexpr double mechanics_settle_s = 4.0;

// The trials for the species file (loaded as the world loads it: an error names the file and field).
Result<SpeciesMechanics> species_mechanics(const std::filesystem::path& species_file, double settle_s = mechanics_settle_s);

} // namespace ikebana::game
