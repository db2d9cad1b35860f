#pragma once
// The channel from the simulation lane to the main lane. The World owns it; each lane's registry holds
// an ecs::Port<FrameChannel> to it (publishing and receiving are both writes of the Port).
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "engine/ecs/entity.hpp"

#include "components/snapshot.hpp"
#include "engine/sched/triple_buffer.hpp"

namespace ikebana::systems {

struct FrameChannel {
    sched::TripleBuffer<components::FrameSnapshot> buffer;
    // The writer's own (the simulation lane's publish_frame): per slot of the buffer, the flower and its
    // child count whose parts each of its flower entries holds, so that an unchanged flower's parts are
    // not copied again; and the flower entities by their index in the frame being written (kept from
    // frame to frame: no allocation on the haptic lane).
    struct WriterSide {
        std::vector<const void*> slots;
        std::vector<std::vector<std::pair<ecs::Entity, std::size_t>>> parts_in_slot;
        std::vector<ecs::Entity> order;
        // Spare entries, made when the scene's BodyCapacity is first seen: a cutting, a piece (a twig,
        // a stalk) or a part that appears in a frame takes one, its memory already there, and one that
        // leaves gives it back, so the lane neither allocates nor frees for them.
        std::vector<components::CuttingStatus> spare_cuttings;
        std::vector<components::TwigStatus> spare_pieces;       // a twig's size
        std::vector<components::TwigStatus> spare_stalk_pieces; // a stalk's (most pieces are; each a stem's size was most of the memory)
        std::size_t stalk_points = 0;
        std::vector<components::Part> spare_parts;
        const void* sized_for = nullptr;
    } writer;
};

// What the main lane has received (main-lane resource).
struct ReceivedFrames {
    std::uint64_t frames = 0;
    std::uint64_t fresh = 0; // frames that brought a new snapshot
    // The newest snapshot, read in place in the channel (no copy): the reader's buffer stays the
    // reader's until the next receive, which only the main lane does.
    const components::FrameSnapshot* current = nullptr;
    [[nodiscard]] const components::FrameSnapshot& latest() const {
        static const components::FrameSnapshot none{};
        return current ? *current : none;
    }
    components::HandStatus previous_hands[2]{};
    // Called on the main lane when something the trainee should hear about happens (a device
    // unplugged or back); the app decides how to say it (a line on the terminal, the HUD).
    std::function<void(const std::string&)> announce;
};

// Restored (ecs::Registry::restore), the counts and the hands as they were; `current` stays in this
// world's own channel and `announce` stays this app's. Whoever restores the channel points `current`
// at its read buffer again.
inline void restore_resource(ReceivedFrames& into, ReceivedFrames&& saved) noexcept {
    into.frames = saved.frames;
    into.fresh = saved.fresh;
    for (int h = 0; h < 2; ++h) into.previous_hands[h] = std::move(saved.previous_hands[h]);
}

} // namespace ikebana::systems
