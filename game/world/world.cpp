#include "game/world/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>

#include <glm/gtc/constants.hpp>

#include "components/appearance.hpp"
#include "components/collision.hpp"
#include "components/flower.hpp"
#include "components/hand.hpp"
#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "components/presentation.hpp"
#include "components/stem.hpp"
#include "engine/core/hash.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "engine/devices/scripted_device.hpp"
#include "engine/ecs/hierarchy.hpp"
#include "game/asset_paths.hpp"
#include "game/kenzan/kenzan_layout.hpp"
#include "game/scene/placement_checks.hpp"
#include "game/world/sample_arrangement.hpp"
#include "systems/collision/collision_module.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "systems/haptics/haptics_module.hpp"
#include "systems/haptics/workspace_view_system.hpp"
#include "systems/insertion/deterioration.hpp"
#include "systems/insertion/insertion_module.hpp"
#include "systems/insertion/structure_reserve.hpp"
#include "systems/physics/physics_module.hpp"
#include "systems/physics/stem_builder.hpp"
#include "systems/presentation/frame_channel.hpp"
#include "systems/presentation/presentation_module.hpp"

namespace ikebana::game {

using namespace components;

namespace {

void add_collision_tag(ecs::Registry& r, ecs::Entity e, CollisionClass c) {
    switch (c) {
    case CollisionClass::active: r.emplace<ActiveCollider>(e); break;
    case CollisionClass::passive: r.emplace<PassiveCollider>(e); break;
    case CollisionClass::inactive: r.emplace<InactiveCollider>(e); break;
    }
}

// A scene's trajectories are in world coordinates: each keyframe within the scene's workspace.
Result<void> keys_within_workspace(const std::vector<devices::Keyframe>& keys) {
    for (const auto& k : keys) {
        const glm::dvec3 p = k.position_m;
        if (std::abs(p.x) > workspace_half_extent_m || std::abs(p.y) > workspace_half_extent_m || std::abs(p.z) > workspace_half_extent_m) {
            char text[200];
            std::snprintf(text, sizeof text, "at %.3f s the hand is at (%.3g, %.3g, %.3g) m, outside the workspace (%.0f m from the origin on each axis)",
                          k.time_s, p.x, p.y, p.z, workspace_half_extent_m);
            return make_error(ErrorCode::invalid_argument, text);
        }
    }
    return {};
}

Result<void> register_systems(World& w, systems::ForceScheme force_scheme, const std::vector<sched::SystemDesc>& main_lane_systems, bool frames) {
    // The lanes' phases, in execution order at equal timestamps.
    if (auto r = w.schedule.add_lane({"sim", &w.sim, sched::LaneThread::own,
                                      {"input", "collision", "insertion", "physics", "constraints", "output", "present"}});
        !r) {
        return r;
    }
    // The main lane: receive the snapshot, take the trainee's input, prepare the frame, draw it.
    if (auto r = w.schedule.add_lane({"main", &w.main, sched::LaneThread::caller, {"receive", "input", "prepare", "draw"}}); !r) return r;
    // Modules in the order their conflicting systems run within a phase: a cut or a scripted hand
    // before a device hand grabs, the hands before the collision and physics they feed.
    if (auto r = systems::install_insertion(w.schedule); !r) return r;
    if (auto r = systems::install_haptics(w.schedule, force_scheme); !r) return r;
    if (auto r = systems::install_collision(w.schedule); !r) return r;
    if (auto r = systems::install_physics(w.schedule); !r) return r;
    if (frames) {
        if (auto r = systems::install_presentation(w.schedule); !r) return r;
    }
    for (const auto& desc : main_lane_systems) {
        if (auto r = w.schedule.add(desc); !r) return r;
    }
    return w.schedule.finalize();
}

} // namespace

components::FlowerLook look_of(const SpeciesDef& sp) {
    return FlowerLook{sp.head_mesh, sp.stem_colour, sp.petal_colour, sp.leaf_colour, sp.head_colour};
}

std::vector<components::Part> parts_of(const SpeciesDef& sp, std::uint32_t point_count) { return parts_of(sp.parts, point_count); }

std::vector<components::Part> parts_of(const std::vector<PartDef>& defs, std::uint32_t point_count) {
    std::vector<Part> out;
    std::uint32_t n = 0; // every part of the flower, for its shade
    for (const auto& def : defs) {
        const auto at = static_cast<std::uint32_t>(std::lround(def.position_along_stem * (point_count - 1)));
        for (std::uint32_t w = 0; w < def.whorls; ++w) {
            // Each inner ring: 80 % as long, 15 degrees more upright, turned half a step.
            const double size = def.size_m * std::pow(0.8, w);
            const double tilt = std::clamp(def.tilt_rad + w * 15.0 * glm::pi<double>() / 180.0, -0.5 * glm::pi<double>() + 0.05, 0.5 * glm::pi<double>() - 0.05);
            for (std::uint32_t k = 0; k < def.count; ++k, ++n) {
                const double angle = 2.0 * glm::pi<double>() * (k + 0.5 * w) / def.count;
                const glm::dvec3 out_dir{std::cos(tilt) * std::cos(angle), std::cos(tilt) * std::sin(angle), std::sin(tilt)};
                // A shade from the part's number alone (the same flower looks the same every time).
                const std::uint32_t h = (n + 1) * 2654435761u;
                const double u = static_cast<double>(h >> 8) / static_cast<double>(1u << 24); // 0..1
                const auto shade = static_cast<float>(1.0 + def.colour_variation * (2.0 * u - 1.0));
                // Without a mesh file: its shape, generated (the renderer asks game/meshes for it by name).
                const std::string mesh = def.mesh.empty() ? part_mesh_name(def.shape) : def.mesh;
                out.push_back(Part{def.kind, at, 0.5 * size * out_dir, mesh, shade, static_cast<float>(def.cup_rad)});
            }
        }
    }
    return out;
}

components::PinResistance pin_resistance_of(const SpeciesDef& sp) {
    PinResistance m{};
    if (sp.hard) {
        m.kind = ResistanceKind::hard_eq6;
        m.cortex_tip_n_per_m = sp.hard->cortex_tip_n_per_m;
        m.cortex_trunk_n_per_m = sp.hard->cortex_trunk_n_per_m;
        m.pith_tip_n_per_m = sp.hard->pith_tip_n_per_m;
        m.pith_trunk_n_per_m = sp.hard->pith_trunk_n_per_m;
        m.pith_diameter_m = sp.hard->pith_diameter_m;
    } else if (sp.soft) {
        m.kind = ResistanceKind::soft_table;
        const std::string base = sp.deterioration.model == "extended" ? sp.deterioration.base_model : sp.deterioration.model;
        m.n_per_m_by_insertion = systems::insertion::expand_deterioration(base, sp.soft->n_per_m_by_insertion);
        m.extension = sp.deterioration.terms;
    }
    m.extension_push_only = sp.deterioration.applies_to == "push";
    m.hold_extension = sp.deterioration.hold_terms;
    m.break_probability_by_insertion = sp.breakage.model == "hazard_by_insertion" ? sp.breakage.probability_by_insertion : std::vector<double>{};
    m.broken_holding_factor = sp.breakage.broken_holding_factor;
    m.broken_seat_loss_m = sp.breakage.broken_seat_loss_m;
    return m;
}

namespace {

// A stem's segments (capsules, the bottom one Active if it meets the pins) and its parts, as its children.
void spawn_stem_parts(ecs::Registry& r, ecs::Entity owner, const std::vector<PartDef>& defs, std::uint32_t point_count, double diameter_m,
                      bool bottom_active) {
    for (std::uint32_t i = 0; i + 1 < point_count; ++i) {
        const ecs::Entity part = r.create();
        r.emplace<Part>(part, PartKind::stem, i, glm::dvec3{0.0}, std::string{});
        r.emplace<Collider>(part, ShapeKind::capsule, glm::dvec3{0.0}, glm::dvec3{0.0}, 0.5 * diameter_m, glm::dvec3{0.0});
        add_collision_tag(r, part, bottom_active && i == 0 ? CollisionClass::active : CollisionClass::passive);
        ecs::attach(r, part, owner);
    }
    const auto parts = parts_of(defs, point_count);
    std::size_t next_part = 0;
    for (const auto& def : defs) {
        for (std::uint32_t k = 0; k < def.count * def.whorls; ++k) { // parts_of's order: each definition's rings, in turn
            const ecs::Entity part = r.create();
            r.emplace<Part>(part, parts[next_part++]);
            r.emplace<Collider>(part, ShapeKind::sphere, glm::dvec3{0.0}, glm::dvec3{0.0}, 0.3 * def.size_m, glm::dvec3{0.0});
            add_collision_tag(r, part, def.collision);
            ecs::attach(r, part, owner);
        }
    }
}

// The twigs `defs` on `parent` (the flower's stem or a twig), and theirs, each listed after its parent.
// Their material is the species' stem's; their size, their place and their side are their own.
// A branch laid on the table lies flat, its twigs with it: each turned to the side across its parent
// that lies along the table nearest the side it grows on, curving along the table.
void spawn_twigs(ecs::Registry& r, const SpeciesDef& sp, const std::vector<BranchDef>& defs, ecs::Entity parent, bool lying,
                 std::vector<ecs::Entity>& list) {
    // Copies: spawning a twig adds to the storages the parent's components live in.
    const StemPoints parent_points = r.get<StemPoints>(parent);
    const StemFrame parent_frame = r.get<StemFrame>(parent);
    const auto segments = static_cast<std::uint32_t>(parent_points.position_m.size() - 1);
    for (const auto& def : defs) {
        for (std::uint32_t k = 0; k < def.count; ++k) {
            const double along = def.position_along_parent + def.spacing * k;
            const auto at_point = static_cast<std::uint32_t>(std::clamp<long>(std::lround(along * segments), 1, segments));
            const double scale = std::pow(1.0 - def.shrink, k);
            systems::physics::StemSpec spec;
            spec.segments = def.segments;
            spec.length_m = def.length_m * scale;
            spec.diameter_m = def.diameter_m;
            spec.youngs_modulus_pa = sp.youngs_modulus_pa;
            spec.poisson_ratio = sp.poisson_ratio;
            spec.shear_modulus_pa = sp.shear_modulus_pa;
            spec.stem_mass_kg = def.mass_kg * scale;
            spec.rest_bend_rad = def.rest_bend_rad;
            spec.stiffness_damping_s = sp.stiffness_damping_s;
            spec.air_drag_per_s = sp.air_drag_per_s;
            // The side it leaves toward, cos a d1 + sin a d2 in the parent's frame, is turned to by the
            // rotation about e x side = cos a d2 - sin a d1 (the fork's direction is its rotation's).
            double side = def.azimuth_rad + def.turn_rad * k;
            glm::dvec3 curve{0.0};
            if (lying) {
                const auto& x = parent_points.position_m;
                const glm::dvec3 e = glm::normalize(x[at_point] - x[at_point - 1]);
                const glm::dvec3 flat = glm::cross(glm::dvec3{0.0, 0.0, 1.0}, e);
                const glm::dvec3 d1 = parent_frame.director[at_point - 1];
                if (glm::length(flat) > 1e-6) {
                    const double along_table = std::atan2(glm::dot(flat, glm::cross(e, d1)), glm::dot(flat, d1));
                    side = std::cos(side - along_table) >= 0.0 ? along_table : along_table + glm::pi<double>();
                    curve = glm::normalize(flat) * (std::cos(side - along_table) >= 0.0 ? 1.0 : -1.0);
                }
            }
            auto twig = systems::physics::build_twig(spec, parent_points, parent_frame, at_point, def.angle_rad, {-std::sin(side), std::cos(side)}, curve);
            twig.fork.parent = parent;
            const ecs::Entity e = r.create();
            const auto point_count = static_cast<std::uint32_t>(twig.stem.points.position_m.size());
            r.emplace<StemPoints>(e, std::move(twig.stem.points));
            r.emplace<StemRestShape>(e, std::move(twig.stem.rest));
            r.emplace<StemSprings>(e, std::move(twig.stem.springs));
            r.emplace<StemFrame>(e, std::move(twig.stem.frame));
            r.emplace<StemLoads>(e, StemLoads{std::vector<glm::dvec3>(point_count, glm::dvec3{0.0})});
            r.emplace<StemFork>(e, twig.fork);
            spawn_stem_parts(r, e, def.parts, point_count, def.diameter_m, false);
            list.push_back(e);
            spawn_twigs(r, sp, def.branches, e, lying, list);
        }
    }
}

} // namespace

ecs::Entity spawn_flower(ecs::Registry& r, const SpeciesDef& sp, const FlowerPlacement& placement, double table_height_m) {
    systems::physics::StemSpec spec;
    spec.segments = sp.segments;
    spec.length_m = sp.length_m;
    spec.diameter_m = sp.diameter_m;
    spec.youngs_modulus_pa = sp.youngs_modulus_pa;
    spec.second_moment_m4 = sp.second_moment_m4;
    spec.poisson_ratio = sp.poisson_ratio;
    spec.shear_modulus_pa = sp.shear_modulus_pa;
    spec.stem_mass_kg = sp.stem_mass_kg;
    spec.head_mass_kg = sp.head_mass_kg;
    spec.rest_bend_rad = sp.rest_bend_rad;
    spec.stiffness_damping_s = sp.stiffness_damping_s;
    spec.air_drag_per_s = sp.air_drag_per_s;
    spec.direction = placement.direction;
    spec.base_m = placement.base_m;
    // Laid on the table (not held up in the air, as the sag trial holds one).
    const bool on_table = placement.placement == Placement::lying && placement.base_m.z <= table_height_m + sp.diameter_m;
    if (placement.placement == Placement::lying) {
        spec.base_m.z = std::max(spec.base_m.z, table_height_m + 0.5 * sp.diameter_m);
        // Its curve, if any, toward the table. On the table a curved stem lies as it would fall, on
        // its two ends with its curve arching between them (laid with its curve rising from its base,
        // it rocked on it): it leaves its base rising by half its curve and curves down.
        const glm::dvec3 d = glm::dvec3{placement.direction.x, placement.direction.y, 0.0};
        if (on_table && sp.rest_bend_rad != 0.0 && glm::length(d) > 1e-9) {
            const double half = 0.5 * sp.rest_bend_rad;
            spec.direction = std::cos(half) * glm::normalize(d) + std::sin(half) * glm::dvec3{0, 0, 1};
        }
        spec.bend_towards = glm::dvec3{0, 0, -1};
    } else {
        // Bend (if any) away from the kenzan's centre line, in a vertical plane.
        spec.bend_towards = glm::dvec3{1, 0, 0};
    }
    auto stem = systems::physics::build_stem(spec);
    // Raised until its lowest point is on the table.
    if (on_table) {
        double lowest = spec.base_m.z;
        for (const auto& x : stem.points.position_m) lowest = std::min(lowest, x.z);
        const double lift = std::max(0.0, table_height_m + 0.5 * sp.diameter_m - lowest);
        for (auto& x : stem.points.position_m) x.z += lift;
        spec.base_m.z += lift;
    }

    const ecs::Entity flower = r.create();
    r.emplace<Flower>(flower, sp.id, sp.total_mass_kg());
    r.emplace<FlowerLook>(flower, look_of(sp));
    // The kenzan grip engages this clamp when the stem stands released in the pins.
    r.emplace<StemClamp>(flower, StemClamp{false, spec.base_m, placement.direction, 0.0});
    r.emplace<PinResistance>(flower, pin_resistance_of(sp));
    // Their lists grow on the 1 kHz lane as the stem goes in and out: room made now, so that they don't
    // allocate there (nothing on that lane may).
    auto& history = r.emplace<InsertionHistory>(flower);
    history.records.reserve(insertion_records_reserved);
    history.holes.reserve(insertion_records_reserved);
    r.emplace<PinEngagement>(flower).pins.reserve(engaged_pins_reserved);
    r.emplace<KenzanGrip>(flower);
    r.emplace<Grasp>(flower);
    Bending bending{};
    bending.permanent_set_rad = sp.permanent_set_rad;
    r.emplace<Bending>(flower, bending);
    const auto point_count = static_cast<std::uint32_t>(stem.points.position_m.size());
    r.emplace<StemPoints>(flower, std::move(stem.points));
    r.emplace<StemRestShape>(flower, std::move(stem.rest));
    r.emplace<StemSprings>(flower, std::move(stem.springs));
    r.emplace<StemFrame>(flower, std::move(stem.frame));
    r.emplace<StemLoads>(flower, StemLoads{std::vector<glm::dvec3>(point_count, glm::dvec3{0.0})});

    // Stem segments: the bottom one meets the pins (Active), the rest are touched (Passive).
    spawn_stem_parts(r, flower, sp.parts, point_count, sp.diameter_m, true);
    if (!sp.branches.empty()) {
        std::vector<ecs::Entity> twigs;
        spawn_twigs(r, sp, sp.branches, flower, placement.placement == Placement::lying, twigs);
        if (placement.placement == Placement::lying) {
            // A branch laid on the table rests on whatever of it reaches lowest, its twigs too: lifted
            // so that nothing starts inside the table (the table pushes a point out one at a time, and a
            // stiff twig's tip pushed out of it by millimetres at once stays squeezed against it).
            double lowest = std::numeric_limits<double>::infinity();
            for (const ecs::Entity e : twigs) {
                const double radius = 0.5 * r.get<StemRestShape>(e).diameter_m;
                for (const auto& x : r.get<StemPoints>(e).position_m) lowest = std::min(lowest, x.z - radius);
            }
            if (lowest < table_height_m) {
                const glm::dvec3 lift{0.0, 0.0, table_height_m - lowest};
                for (auto& x : r.get<StemPoints>(flower).position_m) x += lift;
                for (const ecs::Entity e : twigs) {
                    for (auto& x : r.get<StemPoints>(e).position_m) x += lift;
                }
            }
        }
        r.emplace<Twigs>(flower, Twigs{std::move(twigs)});
    }
    return flower;
}

components::Container container_of(const SceneDef& scene) {
    if (!scene.container) return {};
    // On the table: a bottom and a wall 6 mm thick. A vase is filled up to near its mouth (a kubari,
    // or sand): the kenzan stands there, its pins below the rim.
    const ContainerDef& box = *scene.container;
    const double wall = 0.006;
    const double rim = scene.table_height_m + wall + box.depth_m;
    const bool vase = box.shape == ContainerShape::vase;
    const double floor = vase ? rim - 0.03 : scene.table_height_m + wall;
    return components::Container{box.shape != ContainerShape::rectangular, scene.container_centre_m,
                                 glm::dvec2{0.5 * box.width_m, 0.5 * box.front_to_back_m}, floor, rim, wall,
                                 vase ? rim - 0.01 : floor + box.water_depth_m, scene.table_height_m};
}

Result<std::unique_ptr<World>> World::create(const SceneDef& scene, const WorldOptions& options) {
    std::unique_ptr<World> w(new World());
    // Rates: the paper's defaults, then the scene's, then the command line's.
    for (const auto& [name, hz] : scene.rates_hz) {
        if (auto r = w->schedule.rates().set(name, hz); !r) {
            return make_error(r.error().code, scene.file.filename().string() + ": /rates_hz/" + name + ": " + r.error().message);
        }
    }
    for (const auto& assignment : options.rate_overrides) {
        if (auto r = w->schedule.rates().set_from_string(assignment); !r) return std::move(r).error();
    }
    // Everything the scene names is loaded before anything is spawned: a broken file leaves no
    // half-built world behind.
    // Each error names the scene and the field that named the file, then the file's own message.
    const std::string scene_label = scene.file.empty() ? std::string("scene") : scene.file.filename().string();
    const auto from_scene = [&](const std::string& field, const Error& e) { return make_error(e.code, scene_label + ": " + field + ": " + e.message); };
    // A layout given as a path is looked for beside the scene too; an id is assets/kenzan/<id>.json.
    const bool layout_is_path = scene.kenzan_layout.find('/') != std::string::npos || scene.kenzan_layout.ends_with(".json");
    auto layout_file = layout_is_path ? named_from(scene.file, scene.kenzan_layout) : Result<std::filesystem::path>(std::filesystem::path{});
    if (!layout_file) return from_scene("/kenzan/layout", layout_file.error());
    auto kenzan = load_kenzan(layout_is_path ? layout_file->string() : scene.kenzan_layout);
    if (!kenzan) return from_scene("/kenzan/layout", kenzan.error());
    // The flowers' species, and the sample's (one rule for every file a scene names: a sample stem of a
    // species that does not load, or of /etc/passwd, was once drawn as a grey placeholder).
    std::vector<std::pair<std::string, std::string>> named; // (species, the field that named it)
    for (std::size_t i = 0; i < scene.flowers.size(); ++i) named.emplace_back(scene.flowers[i].species, "/flowers/" + std::to_string(i) + "/species");
    for (std::size_t i = 0; i < scene.sample.size(); ++i) named.emplace_back(scene.sample[i].species, "/sample/" + std::to_string(i) + "/species");
    for (const auto& [species, field] : named) {
        if (w->species.contains(species)) continue;
        // A path is looked for beside the scene, then in the assets folder; an id is assets/species/<id>.json.
        const bool is_path = species.find('/') != std::string::npos || species.ends_with(".json");
        auto where = is_path ? named_from(scene.file, species) : Result<std::filesystem::path>(asset_dir() / "species" / (species + ".json"));
        if (!where) return from_scene(field, where.error());
        auto sp = load_species_file(*where);
        if (!sp) return from_scene(field, sp.error());
        w->species.emplace(species, std::move(sp).value());
    }
    {
        components::Kenzan placed = *kenzan;
        placed.origin_m = scene.kenzan_position_m;
        if (auto ok = check_placements(scene, placed, w->species); !ok) return std::move(ok).error();
    }
    std::vector<std::vector<devices::Keyframe>> trajectories(scene.hands.size());
    for (std::size_t i = 0; i < scene.hands.size(); ++i) {
        if (scene.hands[i].trajectory.empty()) continue;
        auto file = named_from(scene.file, scene.hands[i].trajectory);
        if (!file) return from_scene("/hands/" + std::to_string(i) + "/trajectory", file.error());
        auto keys = devices::load_trajectory(*file);
        if (!keys) return from_scene("/hands/" + std::to_string(i) + "/trajectory", keys.error());
        if (auto inside = keys_within_workspace(*keys); !inside) return from_scene("/hands/" + std::to_string(i) + "/trajectory", inside.error());
        trajectories[i] = std::move(keys).value();
    }

    auto& r = w->sim;
    r.set_resource<systems::insertion::Covariates>(scene.environment);
    r.set_resource<PhysicsSettings>(scene.gravity_m_s2);
    r.set_resource<Table>(scene.table_height_m, 0.6);
    r.set_resource<Contacts>();
    // Each lane's ends of the channels the world owns: using one is a declared write of its Port.
    r.set_resource<ecs::Port<systems::FrameChannel>>(w->channel);
    r.set_resource<ecs::Port<systems::ViewChannel>>(w->view);
    r.set_resource<ecs::Port<systems::TraineeChannel>>(w->trainee);
    w->main.set_resource<ecs::Port<systems::FrameChannel>>(w->channel);
    w->main.set_resource<ecs::Port<systems::ViewChannel>>(w->view);
    w->main.set_resource<ecs::Port<systems::TraineeChannel>>(w->trainee);
    w->main.set_resource<systems::ReceivedFrames>();
    w->main.set_resource<HudInfo>();
    w->main.set_resource<PreparedFrame>();

    const ecs::Entity kenzan_entity = r.create();
    kenzan->origin_m = scene.kenzan_position_m;
    r.emplace<Kenzan>(kenzan_entity, std::move(kenzan).value());
    r.emplace<PassiveCollider>(kenzan_entity);

    const ecs::Entity world_entity = r.create();
    r.emplace<RandomStream>(world_entity, scene.seed * 0x9e3779b97f4a7c15ull + 1);

    if (scene.container) {
        const ecs::Entity container = r.create();
        r.emplace<Container>(container, container_of(scene));
        r.emplace<PassiveCollider>(container);
    }

    const auto& kenzan_now = r.get<Kenzan>(kenzan_entity);
    for (auto f : scene.flowers) {
        SpeciesDef sp = w->species.at(f.species);
        if (f.length_m > 0.0) {
            // A material cut to length before the session: the same stem, shorter and lighter.
            sp.stem_mass_kg *= f.length_m / sp.length_m;
            sp.length_m = f.length_m;
        }
        if (f.placement == Placement::inserted) {
            // Standing in the pins: the stem end's lowest point `inserted_depth` below the pin tips.
            const double lowest_offset = 0.5 * sp.diameter_m * std::sqrt(std::max(0.0, 1.0 - f.direction.z * f.direction.z));
            f.base_m.z = kenzan_now.origin_m.z + kenzan_now.pin_height_m() - f.inserted_depth_m + lowest_offset;
        }
        w->flowers.push_back({spawn_flower(r, sp, f, scene.table_height_m), sp.id});
    }
    r.set_resource<systems::HandDevices>();
    r.set_resource<systems::HandCoupling>();
    r.set_resource<systems::HandLinks>();
    r.set_resource<SentForceLog>();
    for (std::size_t hand_index = 0; hand_index < scene.hands.size(); ++hand_index) {
        const auto& h = scene.hands[hand_index];
        const ecs::Entity hand = r.create();
        r.emplace<HandCube>(hand, h.hand, h.edge_m);
        r.emplace<Collider>(hand, ShapeKind::box, h.position_m, h.position_m, 0.0, glm::dvec3{0.5 * h.edge_m});
        r.emplace<ActiveCollider>(hand);
        r.emplace<HandInput>(hand, HandInput{false, h.position_m, glm::dvec3{0.0}, 0, 0, 0});
        r.emplace<HandProxy>(hand, HandProxy{h.position_m, glm::dvec3{0.0}});
        r.emplace<HandGrip>(hand, HandGrip{ecs::null_entity, 0, glm::dvec3{0.0}, false, 0, glm::dvec3{0.0}, glm::dvec3{0.0}, glm::dquat{1, 0, 0, 0}, 0});
        r.emplace<HandForce>(hand, HandForce{glm::dvec3{0.0}});
        r.emplace<ForceChecks>(hand);
        // Scripted trajectories are in world coordinates.
        r.emplace<WorkspaceMapping>(hand, glm::dvec3{0.0}, 1.0, 0.0, 0.3, 1.2);
        if (h.hand < 2) w->hands[h.hand] = hand;
        if (!h.trajectory.empty()) {
            w->attach_device(h.hand, std::make_unique<devices::ScriptedDevice>(std::move(trajectories[hand_index]), devices::ScriptedDevice::Mode::interpolate,
                                                                               h.trajectory));
        }
    }
    // What a cut or pruning needs at run time, made now: on the 1 kHz lane they allocate nothing.
    systems::reserve_structure_changes(r);
    // The sample to copy, drawn beside the kenzan in every frame (the window's, `render`'s).
    auto& scenery = w->main.set_resource<Scenery>();
    add_sample_to_draw_list(scenery.list, *w, scene.sample);
    const std::string scheme = options.force_scheme.empty() ? scene.force_scheme : options.force_scheme;
    if (scheme != "full_rate" && scheme != "paper") {
        return make_error(ErrorCode::invalid_argument, "force scheme '" + scheme + "': expected full_rate or paper");
    }
    const auto force_scheme = scheme == "paper" ? systems::ForceScheme::paper : systems::ForceScheme::full_rate;
    if (auto ok = register_systems(*w, force_scheme, options.main_lane_systems, options.frames); !ok) return std::move(ok).error();
    return w;
}

void World::attach_device(std::uint8_t hand, std::unique_ptr<devices::HapticDevice> device) {
    if (hand >= 2) return;
    auto* slots = sim.resource<systems::HandDevices>();
    // Every device that can push goes through the one safety layer, whoever opened it.
    hand_devices[hand] = devices::make_force_safe(std::move(device));
    if (slots) slots->attach(hand, hand_devices[hand].get());
    if (auto* coupling = sim.resource<systems::HandCoupling>()) {
        // The coupling this device renders stably: its profile's, capped by its declared maximum.
        const devices::DeviceCapabilities defaults;
        const auto& caps = hand_devices[hand] ? hand_devices[hand]->capabilities() : defaults;
        coupling->n_per_m[hand] = devices::coupling_stiffness_n_per_m(caps);
        coupling->damping_ns_per_m[hand] = devices::coupling_damping_ns_per_m(caps);
    }
    if (auto* hud = main.resource<HudInfo>()) hud->device[hand] = hand_devices[hand] ? hand_devices[hand]->capabilities().name : "no device";
}

std::uint64_t World::state_hash() const {
    StateHasher h;
    h.scalar(sim.state_hash());
    h.scalar(main.state_hash());
    return h.digest();
}

} // namespace ikebana::game
