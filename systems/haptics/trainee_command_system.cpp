#include "systems/haptics/trainee_command_system.hpp"

#include <cstdio>
#include <numeric>

#include "engine/ecs/registry.hpp"

namespace ikebana::systems {

using namespace components;

void TraineeCommandSystem::operator()(sched::SystemContext& ctx) {
    auto& r = ctx.registry;
    auto* port = r.resource<ecs::Port<TraineeChannel>>();
    if (!port) return;
    TraineeChannel& channel = port->use();
    TraineeCommand command;
    while (channel.pop(command)) {
        if (channel.log) {
            char line[96];
            const bool pruning = command.kind == TraineeCommand::Kind::prune;
            const int n = pruning ? std::snprintf(line, sizeof line, "%lld,prune,%u,0\n", static_cast<long long>(ctx.time_us), command.hand)
                                  : std::snprintf(line, sizeof line, "%lld,cut,%u,%.17g\n", static_cast<long long>(ctx.time_us), command.hand, command.keep_length_m);
            (void)channel.log->write(std::string_view(line, static_cast<std::size_t>(n)));
        }
        r.view<const HandCube, const HandGrip>().each([&](ecs::Entity hand, const HandCube& cube, const HandGrip& grip) {
            if (cube.hand != command.hand) return;
            // Pruning needs no held stem: the hand cuts where it is.
            if (command.kind == TraineeCommand::Kind::prune) {
                r.commands().emplace<PruneRequest>(hand, PruneRequest{command.hand});
                return;
            }
            if (grip.held.is_null()) return;
            const auto* rest = r.try_get<const StemRestShape>(grip.held);
            if (!rest) return;
            const double length = std::accumulate(rest->segment_length_m.begin(), rest->segment_length_m.end(), 0.0);
            // Only shorter: a cut cannot lengthen a stem (the cutting system refuses what leaves too little).
            if (command.kind == TraineeCommand::Kind::cut && command.keep_length_m > 0.0 && command.keep_length_m < length) {
                r.commands().emplace<CutRequest>(grip.held, CutRequest{length - command.keep_length_m});
            }
        });
    }
}

} // namespace ikebana::systems
