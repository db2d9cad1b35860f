#include "game/devices/force_watchdogs.hpp"

#include <csignal>
#include <cstring>

#include "engine/core/emergency_stop.hpp"
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

RunEnding how_the_run_ended(const sched::Schedule& schedule, const std::vector<sched::LaneReport>& lanes) {
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        if (lanes[i].failure.empty()) continue;
        const std::string lane = i < schedule.lanes().size() ? schedule.lanes()[i].name : std::to_string(i);
        return {"the " + lane + " lane failed (" + lanes[i].failure + "); the run was stopped and " + std::to_string(lanes[i].zeroed_devices) +
                    " pushing device(s) sent zero force at once",
                1};
    }
    return stopped_by_signal();
}

RunEnding stopped_by_signal() {
    const int signal_number = stop_signal();
    if (signal_number == 0) return {};
    const char* name = signal_number == SIGINT ? "SIGINT (Ctrl-C)" : signal_number == SIGTERM ? "SIGTERM" : strsignal(signal_number);
    return {std::string("ended by ") + name + "; every pushing device was sent zero force", 128 + signal_number};
}

} // namespace ikebana::game
