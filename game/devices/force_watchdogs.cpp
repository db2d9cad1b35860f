#include "game/devices/force_watchdogs.hpp"

#include "game/world/world.hpp"
#include "systems/haptics/hand_devices.hpp"

namespace ikebana::game {

HandForceWatchdogs::HandForceWatchdogs(World& world) : world_(world) {
    auto* slots = world_.sim.resource<systems::HandDevices>();
    if (!slots) return;
    for (std::size_t hand = 0; hand < 2; ++hand) {
        auto* device = world_.hand_devices[hand].get();
        if (!device || !device->capabilities().has_force_output) continue;
        dogs_[hand] = std::make_unique<devices::ForceWatchdog>([device] { (void)device->zero_force(); });
        slots->feed_after_sending(hand, dogs_[hand].get());
    }
}

HandForceWatchdogs::~HandForceWatchdogs() {
    if (auto* slots = world_.sim.resource<systems::HandDevices>()) {
        for (std::size_t hand = 0; hand < 2; ++hand) {
            if (dogs_[hand]) slots->feed_after_sending(hand, nullptr);
        }
    }
}

} // namespace ikebana::game
