#include "game/cli/sim_command.hpp"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <unistd.h>

#include "engine/core/emergency_stop.hpp"
#include "engine/devices/hid_transport.hpp"
#include "engine/sched/clocks.hpp"
#include "components/hand.hpp"
#include "engine/devices/safe_force_device.hpp"
#include "engine/devices/scripted_device.hpp"
#include "engine/assets/files.hpp"
#include "game/asset_paths.hpp"
#include "game/cli/option_checks.hpp"
#include "game/devices/force_watchdogs.hpp"
#include "game/devices/hand_device_selection.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "game/world/summary.hpp"
#include "game/world/world.hpp"

namespace ikebana::game {

int run_sim(const SimOptions& options) {
    auto scene = with_environment(load_scene(options.scene), options.env);
    if (!scene) {
        std::cerr << "ikebana sim: " << scene.error().message << "\n";
        return 2;
    }
    auto world = World::create(*scene, WorldOptions{.rate_overrides = options.rates, .force_scheme = options.force_scheme, .main_lane_systems = {}});
    if (!world) {
        std::cerr << "ikebana sim: " << world.error().message << "\n";
        return 2;
    }
    World& w = **world;
    for (const auto& warning : startup_warnings(w)) std::cerr << "ikebana sim: " << warning << "\n";
    // Devices: the command line overrides the scene, hand by hand.
    const std::string* specs[2] = {&options.left_device, &options.right_device};
    for (std::uint8_t hand = 0; hand < 2; ++hand) {
        if (specs[hand]->empty()) continue;
        auto opened = open_hand_device(*specs[hand], hand);
        if (!opened) {
            std::cerr << "ikebana sim: " << (hand ? "--right: " : "--left: ") << opened.error().message << "\n";
            return 2;
        }
        std::printf("%s hand: %s\n", hand ? "right" : "left", opened->description.c_str());
        w.attach_device(hand, std::move(opened->device));
    }
    // Device news reaches the terminal when it happens (on the main lane, in simulated time order).
    if (auto* frames = w.main.resource<systems::ReceivedFrames>()) {
        frames->announce = [](const std::string& message) {
            std::printf("ikebana: %s\n", message.c_str());
            std::fflush(stdout);
        };
    }
    std::unique_ptr<std::ostream> record_files[2];
    std::unique_ptr<devices::DeviceRecorder> recorders[2];
    std::error_code exists_error;
    const bool record_folder_was_there = !options.record_dir.empty() && std::filesystem::exists(options.record_dir, exists_error);
    if (!options.record_dir.empty()) {
        if (auto folder = assets::create_output_folder(options.record_dir); !folder) {
            std::cerr << "ikebana sim: --record: " << folder.error().message << "\n";
            return 2;
        }
        auto* slots = w.sim.resource<systems::HandDevices>();
        for (int hand = 0; hand < 2; ++hand) {
            const auto path = std::filesystem::path(options.record_dir) / (hand ? "right.csv" : "left.csv");
            auto file = assets::open_output_stream(path);
            if (!file) {
                std::cerr << "ikebana sim: --record: " << file.error().message << "\n";
                return 2;
            }
            record_files[hand] = std::move(*file);
            // In real time a disk seconds behind costs samples (counted below), never the haptic loop's time.
            recorders[hand] = std::make_unique<devices::DeviceRecorder>(
                *record_files[hand], options.realtime ? AsyncLineWriter::WhenFull::drop : AsyncLineWriter::WhenFull::wait);
            // Said the moment the disk refuses (from the writer's thread), and again at the end.
            recorders[hand]->on_failure([path](const std::string& why) {
                std::fprintf(stderr, "ikebana sim: --record: %s: %s; the recording stops here\n", path.c_str(), why.c_str());
            });
            slots->record_to(static_cast<std::size_t>(hand), recorders[hand].get());
        }
        std::printf("recording every device sample to %s/{left,right}.csv (replay with --left replay:FILE)\n", options.record_dir.c_str());
    }
    const auto wall_start = std::chrono::steady_clock::now();
    if (options.realtime && !options.count_lane.empty()) {
        std::cerr << "ikebana sim: --count-lane counts a run on the deterministic clock, not --realtime\n";
        return 2;
    }
    RunEnding ended;
    double simulated_s = options.seconds;
    if (options.realtime) {
        std::printf("running %.1f s in real time (simulation lane on its own thread)...\n", options.seconds);
        std::fflush(stdout);
        // Ctrl-C and SIGTERM end the run the ordinary way, which zeroes every device; a throw or
        // std::terminate zeroes them on the spot (engine/core/emergency_stop.hpp).
        install_stop_signals();
        install_terminate_handler();
        const HandForceWatchdogs watchdogs(w);
        sched::RealtimeClock clock(w.schedule, sched::RealtimeConfig{.max_catchup_us = 50'000, .own_thread_timer_slack_ns = 1'000,
                                                                     .own_thread_fifo_priority = devices::haptic_lane_fifo_priority,
                                     .lock_memory = true, .on_skip = {}});
        const auto reports = clock.run_for(options.seconds);
        ended = how_the_run_ended(w.schedule, reports);
        if (ended.exit_code != 0) {
            // Ended early: the summary speaks of the time the simulation reached, not the time asked.
            std::int64_t reached_us = 0;
            for (const auto& s : w.schedule.systems()) {
                if (w.schedule.lanes()[s.lane].name == "sim") reached_us = std::max(reached_us, s.next_due_us);
            }
            simulated_s = static_cast<double>(reached_us) * 1e-6;
        }
        // Nothing pushes after the run (the watchdogs stop with this block).
        for (auto& device : w.hand_devices) {
            if (device) (void)device->zero_force();
        }
        for (std::size_t hand = 0; hand < 2; ++hand) {
            if (!watchdogs.armed(hand)) continue;
            std::printf("%s hand force watchdog: tripped %llu time(s)\n", hand ? "right" : "left",
                        static_cast<unsigned long long>(watchdogs.trips(hand)));
        }
        std::printf("%s", format_realtime_report(w, reports).c_str());
        if (ended.exit_code != 0) std::fprintf(stderr, "ikebana sim: %s\n", ended.why.c_str());
    } else {
        sched::DeterministicClock clock(w.schedule);
        if (!options.count_lane.empty()) {
            const auto& lanes = w.schedule.lanes();
            std::optional<std::size_t> lane;
            for (std::size_t i = 0; i < lanes.size(); ++i) {
                if (lanes[i].name == options.count_lane) lane = i;
            }
            if (!lane) {
                std::string names;
                for (const auto& l : lanes) names += (names.empty() ? "" : ", ") + l.name;
                std::cerr << "ikebana sim: --count-lane: no lane '" << options.count_lane << "' (lanes: " << names << ")\n";
                return 2;
            }
            clock.count_instructions_of_lane(lane);
        }
        const auto print_ticks = [&] {
            const auto& lanes = w.schedule.lanes();
            for (std::size_t i = 0; i < clock.tick_ns().size(); ++i) {
                const auto& t = clock.tick_ns()[i];
                std::printf("lane %-5s tick (everything due at one time): p50 %.1f us, p99 %.1f us, max %.1f us over %" PRIu64 " ticks\n",
                            lanes[i].name.c_str(), static_cast<double>(t.percentile(0.5)) / 1e3,
                            static_cast<double>(t.percentile(0.99)) / 1e3, static_cast<double>(t.max()) / 1e3, t.count());
            }
        };
        const auto total_us = static_cast<std::int64_t>(options.seconds * 1e6);
        // Progress on a terminal for long runs; nothing in pipes and logs.
        const bool tty = isatty(fileno(stderr)) != 0;
        const std::int64_t chunk = 1'000'000;
        for (std::int64_t t = 0; t < total_us; t += chunk) {
            clock.run_until(std::min(total_us, t + chunk));
            if (tty && total_us > 5 * chunk) {
                std::fprintf(stderr, "\r%5.1f / %.1f s simulated", static_cast<double>(clock.now_us()) / 1e6, options.seconds);
            }
        }
        if (tty && total_us > 5 * chunk) std::fprintf(stderr, "\n");
        if (options.stats) print_ticks();
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    std::printf("%s", format_summary(summarize(w), simulated_s).c_str());
    for (std::uint8_t hand = 0; hand < 2; ++hand) {
        if (w.hands[hand].is_null()) continue;
        const auto& input = w.sim.get<components::HandInput>(w.hands[hand]);
        const auto& grip = w.sim.get<components::HandGrip>(w.hands[hand]);
        const auto* device = w.hand_devices[hand].get();
        // What the device felt: the force after the safety chain (for a scripted or replayed hand,
        // what a real device would have felt on that trajectory).
        std::string felt;
        if (const auto* safe = dynamic_cast<const devices::SafeForceDevice*>(device)) {
            const auto counters = safe->counters();
            const auto& asked = w.sim.get<components::HandForce>(w.hands[hand]).force_n;
            const auto* links = w.sim.resource<const systems::HandLinks>();
            char text[320];
            std::snprintf(text, sizeof text,
                          ", force after the safety chain at most %.2f N, at the end %.2f N of the %.2f N asked (%llu clamped, %llu rate-limited, "
                          "%llu stalls, %llu engagements, %llu failed writes)",
                          safe->peak_output_n(), glm::length(safe->last_output()), glm::length(asked), static_cast<unsigned long long>(counters.clamped),
                          static_cast<unsigned long long>(counters.rate_limited), static_cast<unsigned long long>(counters.stalls),
                          static_cast<unsigned long long>(counters.engagements),
                          static_cast<unsigned long long>(links ? links->write_failures[hand] : 0));
            felt = text;
        }
        std::printf("%s hand: %s, %s, %llu disconnect(s)%s%s\n", hand ? "right" : "left",
                    device ? device->capabilities().name.c_str() : "no device", input.connected ? "connected" : "not connected",
                    static_cast<unsigned long long>(input.disconnects), grip.held.is_null() ? "" : ", holding a flower", felt.c_str());
    }
    // A recording the disk refused part of would not replay: said, removed (nothing half-made is left),
    // and the run fails.
    std::string recording_failed;
    for (int hand = 0; hand < 2; ++hand) {
        if (!recorders[hand]) continue;
        recorders[hand]->flush();
        if (recorders[hand]->failed() && recording_failed.empty()) {
            recording_failed = std::string(hand ? "right.csv" : "left.csv") + ": " + recorders[hand]->failure();
        }
    }
    if (!recording_failed.empty()) {
        std::error_code ec;
        for (const char* name : {"left.csv", "right.csv"}) std::filesystem::remove(std::filesystem::path(options.record_dir) / name, ec);
        if (!record_folder_was_there) std::filesystem::remove(options.record_dir, ec);
        std::fprintf(stderr, "ikebana sim: --record: %s: not written whole (%s); removed, as it would not replay\n", options.record_dir.c_str(),
                     recording_failed.c_str());
    }
    for (int hand = 0; hand < 2; ++hand) {
        if (recorders[hand] && recorders[hand]->dropped() > 0) {
            std::printf("%s hand: %llu samples not recorded (the disk fell behind): a replay will part from this run\n", hand ? "right" : "left",
                        static_cast<unsigned long long>(recorders[hand]->dropped()));
        }
    }
    std::printf("wall time %.3f s (%.1fx real time)\n", wall, wall > 0 ? simulated_s / wall : 0.0);
    if (options.stats) {
        std::printf("\n%s", w.schedule.stats_table().c_str());
        // Declarations this run did not use (a system that never met what it handles says so too).
        for (const auto& line : w.schedule.unused_access()) std::printf("declared, unused in this run: %s\n", line.c_str());
    }
    if (options.hash) std::printf("state-hash: %016" PRIx64 "\n", w.state_hash());
    if (ended.exit_code != 0) return ended.exit_code;
    return recording_failed.empty() ? 0 : 1;
}

void add_sim_command(CLI::App& app, int& exit_code) {
    auto options = std::make_shared<SimOptions>();
    options->scene = (asset_dir() / "scenes" / "default.json").string();
    auto* sim = app.add_subcommand("sim", "Run a scene headless on the deterministic clock and print a summary");
    sim->add_option("--scene", options->scene, "Scene file")->capture_default_str();
    sim->add_option("--seconds", options->seconds, "Simulated seconds")->capture_default_str()->check(simulated_seconds());
    sim->add_flag("--stats", options->stats, "Print per-system statistics (calls, mean, p99, max, lateness, missed)");
    sim->add_flag("--hash", options->hash, "Print the final state hash as the last line (state-hash: <hex>)");
    sim->add_flag("--realtime", options->realtime, "Pace by the wall clock, simulation lane on its own thread");
    sim->add_option("--left", options->left_device, "Left hand's device: auto, none, scripted:FILE, replay:FILE, hid:PATH");
    sim->add_option("--right", options->right_device, "Right hand's device (as --left)");
    sim->add_option("--force-scheme", options->force_scheme, "full_rate (forces every tick) or paper (16 Hz check, 100 Hz estimate, reused 10 times)")
        ->check(CLI::IsMember({"full_rate", "paper"}));
    sim->add_option("--record", options->record_dir, "Record every device sample of each hand into this folder");
    sim->add_option("--env", options->env, "Set an environment covariate for extended species, e.g. --env humidity_pct=70 --env vase=metal");
    sim->add_option("--count-lane", options->count_lane,
                    "With valgrind --tool=callgrind --collect-atstart=no: count instructions only while this lane's systems run (sim: the haptic tick; main)");
    sim->add_option("--rate", options->rates, "Change a rate, e.g. --rate render=60 (haptic, position_estimate, position_check, render)");
    sim->callback([options, &exit_code] { exit_code = run_sim(*options); });
}

} // namespace ikebana::game
