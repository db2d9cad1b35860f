#pragma once
// A running world: the simulation lane (physics, contacts, later haptics and insertion; its own thread
// at 1 kHz in real time), the main lane (presentation), the schedule over both, and the channel
// between them. `sim`, `experiment`, tests and the app all build their world here, so they run the
// same systems.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include <array>

#include "components/appearance.hpp"
#include "components/insertion.hpp"
#include "components/physics.hpp"
#include "engine/devices/haptic_device.hpp"
#include "engine/core/result.hpp"
#include "engine/ecs/registry.hpp"
#include "engine/sched/schedule.hpp"
#include "game/scene/scene.hpp"
#include "game/species/species.hpp"
#include "systems/haptics/trainee_command_system.hpp"
#include "systems/haptics/workspace_view_system.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::game {

// The scene's container as the World puts it on the table (6 mm wall and bottom; a vase filled up to
// near its mouth), for whoever plans around it before the World exists (the teacher's demonstration).
[[nodiscard]] components::Container container_of(const SceneDef& scene);

struct WorldOptions {
    std::vector<std::string> rate_overrides; // "name=hz", applied after the scene's own rates
    std::string force_scheme;                // overrides the scene's ("full_rate" or "paper")
    // More systems for the main lane, by phase: "input" (the window's keys and camera) and "draw" (the
    // window's present, `render`'s offscreen images), registered with the world's own before the
    // schedule is finalized.
    std::vector<sched::SystemDesc> main_lane_systems;
    // false: no frame is published or prepared (headless runs that draw nothing: the experiment's
    // trials, the predictor's insertions). They spent 5 % of their time building draw lists.
    bool frames = true;
};

struct SpawnedFlower {
    ecs::Entity entity;
    std::string species;
};

class World {
public:
    static Result<std::unique_ptr<World>> create(const SceneDef& scene, const WorldOptions& options = {});

    ecs::Registry sim;
    ecs::Registry main;
    sched::Schedule schedule;
    systems::FrameChannel channel; // simulation -> main thread: what to draw and show
    systems::ViewChannel view;     // main thread -> simulation: where the camera looks
    systems::TraineeChannel trainee; // main thread (or a scripted trainee) -> simulation: cut the held stem
    std::map<std::string, SpeciesDef> species;
    std::vector<SpawnedFlower> flowers;
    std::array<std::unique_ptr<devices::HapticDevice>, 2> hand_devices;
    std::array<ecs::Entity, 2> hands{ecs::null_entity, ecs::null_entity};

    // Puts a device on a hand (replacing any), or takes it away with nullptr (as if unplugged).
    void attach_device(std::uint8_t hand, std::unique_ptr<devices::HapticDevice> device);

    // Both lanes, in lane order.
    [[nodiscard]] std::uint64_t state_hash() const;

private:
    World() = default;
};

// The species' resistance, deterioration and breakage as the insertion systems use them.
components::FlowerLook look_of(const SpeciesDef& species);
// A species' petals and leaves on a stem of `point_count` mass points: each part definition's count
// spread round the stem at its place along it (what a spawned flower carries, and what a drawn model
// flower shows). In the order of the definitions, then round the stem.
std::vector<components::Part> parts_of(const SpeciesDef& species, std::uint32_t point_count);
std::vector<components::Part> parts_of(const std::vector<PartDef>& parts, std::uint32_t point_count);
components::PinResistance pin_resistance_of(const SpeciesDef& species);

// Adds one flower of `species` to `registry`: the flower entity carries the stem physics, and owns one
// part entity per stem segment, petal and leaf, each with its collision tag. Its side branches (the
// species' "branches") are entities of their own, each a stem with a StemFork, owning its segments and
// parts likewise, and listed on the flower (components::Twigs), parents first.
ecs::Entity spawn_flower(ecs::Registry& registry, const SpeciesDef& species, const FlowerPlacement& placement,
                         double table_height_m);

} // namespace ikebana::game
