#include "systems/presentation/publish_frame_system.hpp"

#include "engine/ecs/hierarchy.hpp"
#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

namespace {

// An entry appended from its pool (its memory kept from before), or made when the pool is empty.
template <typename T>
T& take(std::vector<T>& into, std::vector<T>& pool) {
    if (pool.empty()) return into.emplace_back();
    into.push_back(std::move(pool.back()));
    pool.pop_back();
    return into.back();
}
// The entries past `keep` back to their pool, their memory with them.
template <typename T>
void give_back(std::vector<T>& from, std::size_t keep, std::vector<T>& pool) {
    while (from.size() > keep) {
        pool.push_back(std::move(from.back()));
        from.pop_back();
    }
}
// Pieces come in two sizes: a stalk's, and a twig's or stem's. Each goes back to the pool of its size.
std::vector<TwigStatus>& pool_of(const TwigStatus& piece, FrameChannel::WriterSide& w) {
    return piece.points_m.capacity() <= w.stalk_points ? w.spare_stalk_pieces : w.spare_pieces;
}
void pieces_from(std::vector<TwigStatus>& v, std::size_t n, bool stalk, FrameChannel::WriterSide& w) {
    while (v.size() > n) {
        pool_of(v.back(), w).push_back(std::move(v.back()));
        v.pop_back();
    }
    while (v.size() < n) take(v, stalk && !w.spare_stalk_pieces.empty() ? w.spare_stalk_pieces : w.spare_pieces);
}

// The pools and every list a frame holds, sized for the scene's capacity in each of the three slots.
void size_for(const BodyCapacity& c, FrameChannel& channel) {
    auto& w = channel.writer;
    w.sized_for = &c;
    w.stalk_points = c.stalk_points;
    const std::size_t twigs = c.pieces - c.stalks;
    // Every piece can be in a flower's twigs or a cutting's pieces of each slot, or in its pool.
    w.spare_cuttings.reserve(w.spare_cuttings.size() + 3 * c.cuttings);
    w.spare_pieces.reserve(w.spare_pieces.size() + 6 * twigs);
    w.spare_stalk_pieces.reserve(w.spare_stalk_pieces.size() + 3 * c.stalks);
    w.spare_parts.reserve(w.spare_parts.size() + 6 * c.parts);
    for (std::size_t i = 0; i < 3 * c.cuttings; ++i) {
        auto& cutting = w.spare_cuttings.emplace_back();
        cutting.look.head_mesh.reserve(c.mesh_name);
        cutting.pieces.reserve(c.tree_chains + 1); // a branch and its twigs, or a stalk
    }
    const auto add_pieces = [&](std::vector<TwigStatus>& pool, std::size_t count, std::size_t points, std::size_t parts) {
        for (std::size_t i = 0; i < count; ++i) {
            auto& piece = pool.emplace_back();
            piece.points_m.reserve(points);
            piece.directors.reserve(points);
            piece.parts.reserve(parts);
        }
    };
    add_pieces(w.spare_pieces, 3 * twigs, c.points, c.piece_parts);
    add_pieces(w.spare_stalk_pieces, 3 * c.stalks, c.stalk_points, 1);
    for (std::size_t i = 0; i < 3 * c.parts; ++i) w.spare_parts.emplace_back().mesh.reserve(c.mesh_name);
    w.order.reserve(c.bodies);
}

// A twig, or a loose piece, as drawn: its points, bark, thickness and parts.
void piece_of(ecs::Registry& r, ecs::Entity e, TwigStatus& out, FrameChannel::WriterSide& pools) {
    const auto* points = r.try_get<const StemPoints>(e);
    const auto* rest = r.try_get<const StemRestShape>(e);
    const auto* frame = r.try_get<const StemFrame>(e);
    if (points) out.points_m = points->position_m;
    else out.points_m.clear();
    if (frame) out.directors = frame->director;
    else out.directors.clear();
    out.diameter_m = rest ? rest->diameter_m : 0.0;
    // Assigned over the slot's earlier parts: their mesh names keep their memory (a clear and a copy
    // allocated every name, every frame, on the 1 kHz lane).
    std::size_t used = 0;
    if (const auto* children = r.try_get<const ecs::Children>(e)) {
        for (const ecs::Entity child : children->entities) {
            const auto* part = r.try_get<const Part>(child);
            if (!part || part->kind == PartKind::stem || part->mesh.empty()) continue;
            if (used < out.parts.size()) out.parts[used] = *part;
            else take(out.parts, pools.spare_parts) = *part;
            ++used;
        }
    }
    give_back(out.parts, used, pools.spare_parts);
}

} // namespace

void PublishFrameSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    auto* port = r.resource<ecs::Port<FrameChannel>>();
    if (!port) return;
    FrameChannel& channel = port->use();
    const auto* capacity = r.resource<const BodyCapacity>();
    if (capacity && capacity != channel.writer.sized_for) size_for(*capacity, channel);
    auto& pools = channel.writer;
    auto& slots = channel.writer.slots;
    auto& parts_in_slot = channel.writer.parts_in_slot;
    // The writer's slot is reused: its vectors keep their capacity from frame to frame.
    auto& frame = channel.buffer.write_buffer();
    if (capacity && frame.cuttings.capacity() < capacity->cuttings) frame.cuttings.reserve(capacity->cuttings); // each slot once
    frame.sim_time_us = ctx.time_us;
    std::size_t count = 0;
    auto& order = channel.writer.order; // flower entities by their index in the frame
    order.clear();
    // Which of the three slots this is, for the parts it already holds.
    std::size_t slot = 0;
    while (slot < slots.size() && slots[slot] != &frame) ++slot;
    if (slot == slots.size()) {
        slots.push_back(&frame);
        parts_in_slot.emplace_back();
    }
    r.view<const Flower, const StemPoints, const StemRestShape, const FlowerLook>().each(
        [&](ecs::Entity e, const Flower& flower, const StemPoints& points, const StemRestShape& rest, const FlowerLook& look) {
            if (frame.flowers.size() <= count) frame.flowers.emplace_back();
            auto& status = frame.flowers[count++];
            order.push_back(e);
            status.species = flower.species;
            status.points_m = points.position_m;
            if (const auto* bark = r.try_get<const StemFrame>(e)) status.directors = bark->director;
            else status.directors.clear();
            status.diameter_m = rest.diameter_m;
            status.look = look;
            // Twigs: their points move every frame; their parts are few (copied each time, at the render rate).
            const auto* twigs = r.try_get<const Twigs>(e);
            const std::size_t twig_count = twigs ? twigs->entities.size() : 0;
            pieces_from(status.twigs, twig_count, false, pools);
            for (std::size_t t = 0; t < twig_count; ++t) piece_of(r, twigs->entities[t], status.twigs[t], pools);
            status.insertions = 0;
            status.bottom_broken = false;
            status.in_kenzan = false;
            status.fallen = false;
            status.fall_reason = FallReason::none;
            status.fall_yield_holding_nm = 0.0;
            status.fall_yield_gravity_nm = 0.0;
            status.holding_moment_nm = 0.0;
            status.gravity_moment_nm = 0.0;
            status.pins_engaged = 0;
            status.depth_m = 0.0;
            if (const auto* h = r.try_get<const InsertionHistory>(e)) {
                status.insertions = h->insertions_total;
                status.bottom_broken = h->bottom_broken;
            }
            if (const auto* engagement = r.try_get<const PinEngagement>(e)) {
                status.in_kenzan = engagement->in_kenzan;
                status.holding_moment_nm = engagement->holding_moment_nm;
                status.gravity_moment_nm = engagement->gravity_moment_nm;
                status.pins_engaged = static_cast<std::uint32_t>(engagement->pins.size());
                status.depth_m = engagement->depth_m;
            }
            if (const auto* grip = r.try_get<const KenzanGrip>(e)) {
                status.fallen = grip->fallen;
                status.fall_reason = grip->fall_reason;
                if (grip->yielded) {
                    status.fall_yield_holding_nm = grip->yield_holding_nm;
                    status.fall_yield_gravity_nm = grip->yield_gravity_nm;
                }
            }
            // A flower's parts are made with it and never change (the part entities are its children,
            // created at spawn): a slot that already holds this flower's parts, from as many children,
            // keeps them. Copying hundreds of parts a frame was most of this system's time on the
            // haptic lane. Otherwise they are assigned over the slot's earlier ones (strings keep
            // their memory).
            const auto* children = r.try_get<const ecs::Children>(e);
            const std::size_t child_count = children ? children->entities.size() : 0;
            auto& held = parts_in_slot[slot];
            if (held.size() <= count - 1) held.resize(count);
            if (held[count - 1] == std::pair{e, child_count}) return;
            held[count - 1] = {e, child_count};
            std::size_t used = 0;
            if (children) {
                for (const ecs::Entity child : children->entities) {
                    const auto* part = r.try_get<const Part>(child);
                    if (!part || part->kind == PartKind::stem || part->mesh.empty()) continue;
                    if (used < status.parts.size()) status.parts[used] = *part;
                    else take(status.parts, pools.spare_parts) = *part;
                    ++used;
                }
            }
            give_back(status.parts, used, pools.spare_parts);
        });
    frame.flowers.resize(count);
    // What was pruned off, lying loose.
    std::size_t cuttings = 0;
    r.view<const Cutting, const StemPoints>().each([&](ecs::Entity e, const Cutting&, const StemPoints& points) {
        if (frame.cuttings.size() <= cuttings) take(frame.cuttings, pools.spare_cuttings);
        auto& out = frame.cuttings[cuttings++];
        const auto* look = r.try_get<const FlowerLook>(e);
        // (Not `look ? *look : FlowerLook{}`: that copies the look, its head mesh's name a heap allocation a frame.)
        if (look) out.look = *look;
        else out.look = FlowerLook{};
        const auto* twigs = r.try_get<const Twigs>(e);
        pieces_from(out.pieces, 1 + (twigs ? twigs->entities.size() : 0), points.position_m.size() <= pools.stalk_points, pools);
        piece_of(r, e, out.pieces[0], pools);
        for (std::size_t t = 1; t < out.pieces.size(); ++t) piece_of(r, twigs->entities[t - 1], out.pieces[t], pools);
    });
    give_back(frame.cuttings, cuttings, pools.spare_cuttings);
    parts_in_slot[slot].resize(count); // entries dropped with their flowers are not remembered
    for (auto& h : frame.hands) h = HandStatus{false, false, 0, false, glm::dvec3{0.0}, glm::dvec3{0.0}, 0.0, -1, glm::dvec3{0.0}, false};
    r.view<const HandCube, const HandInput, const HandProxy, const HandGrip, const HandForce>().each(
        [&](ecs::Entity, const HandCube& cube, const HandInput& input, const HandProxy& proxy, const HandGrip& grip, const HandForce& force) {
            if (cube.hand < 2) {
                std::int32_t held = -1;
                for (std::size_t i = 0; i < order.size(); ++i) {
                    if (order[i] == grip.held) held = static_cast<std::int32_t>(i);
                }
                HandStatus status{true, input.connected, input.disconnects, !grip.held.is_null(), force.force_n,
                                  proxy.position_m, cube.edge_m, held, input.device_m, (input.buttons & 1u) != 0};
                // What the device really got, after the safety chain, and the state of its link.
                if (const auto* devices = r.resource<const HandDevices>()) status.sent = devices->last_sent(cube.hand);
                if (const auto* links = r.resource<const HandLinks>()) {
                    status.link = input.connected ? DeviceLink::answering : links->link[cube.hand];
                    status.write_failures = links->write_failures[cube.hand];
                }
                frame.hands[cube.hand] = status;
            }
        });
    const auto* contacts = r.resource<const Contacts>();
    frame.contacts = contacts ? contacts->list.size() : 0;
    const auto* kenzan = r.single<const Kenzan>();
    frame.kenzan = kenzan ? std::optional<Kenzan>(*kenzan) : std::nullopt;
    const auto* table = r.resource<const Table>();
    frame.table_height_m = table ? std::optional<double>(table->height_m) : std::nullopt;
    const auto* container = r.single<const Container>();
    frame.container = container ? std::optional<Container>(*container) : std::nullopt;
    channel.buffer.publish();
}

} // namespace ikebana::systems
