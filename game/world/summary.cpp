#include "game/world/summary.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include <glm/gtc/constants.hpp>

#include "components/collision.hpp"
#include "components/hand.hpp"
#include "components/flower.hpp"
#include "components/insertion.hpp"
#include "components/kenzan.hpp"
#include "components/physics.hpp"
#include "systems/insertion/deterioration.hpp"
#include "systems/physics/stem_dynamics.hpp"

namespace ikebana::game {

using namespace components;

WorldSummary summarize(World& w) {
    WorldSummary s;
    auto& r = w.sim;
    s.flowers = r.count<Flower>();
    s.active_parts = r.view<Part, ActiveCollider>().size();
    s.passive_parts = r.view<Part, PassiveCollider>().size();
    s.inactive_parts = r.view<Part, InactiveCollider>().size();
    s.hands = r.count<HandCube>();
    r.view<Kenzan>().each([&](ecs::Entity, Kenzan& k) {
        for (std::int32_t c = 0; c < k.columns; ++c) {
            for (std::int32_t row = 0; row < k.rows; ++row) s.kenzan_pins += k.has_pin(c, row) ? 1 : 0;
        }
    });
    if (const auto* contacts = r.resource<Contacts>()) s.contacts = contacts->list.size();
    const auto* settings = r.resource<PhysicsSettings>();
    const glm::dvec3 g = settings ? settings->gravity_m_s2 : PhysicsSettings{}.gravity_m_s2;
    std::map<ecs::Entity, double> elastic_of; // each stem's, for its flower's line below (computed once)
    r.view<StemPoints, StemRestShape, StemSprings>().each(
        [&](ecs::Entity e, StemPoints& p, StemRestShape& rest, StemSprings& springs) {
            const auto energy = systems::physics::stem_energy(p, rest, springs, r.try_get<StemClamp>(e), g);
            elastic_of[e] = energy.elastic_j;
            s.kinetic_j += energy.kinetic_j;
            s.elastic_j += energy.elastic_j;
            s.gravitational_j += energy.gravitational_j;
            for (const auto& x : p.position_m) s.highest_point_m = std::max(s.highest_point_m, x.z);
        });
    if (const auto* frames = w.main.resource<systems::ReceivedFrames>()) s.frames_received = frames->fresh;
    for (const auto& f : w.flowers) {
        FlowerSummary fs;
        fs.species = f.species;
        if (const auto* h = r.try_get<InsertionHistory>(f.entity)) {
            fs.insertions = h->insertions;
            fs.broken = h->bottom_broken;
        }
        if (const auto* e = r.try_get<PinEngagement>(f.entity)) {
            fs.in_kenzan = e->in_kenzan;
            fs.pins = e->pins.size();
            fs.depth_m = e->depth_m;
            fs.resistance_n = e->resistance_n;
            fs.holding_moment_nm = e->holding_moment_nm;
            fs.gravity_moment_nm = e->gravity_moment_nm;
        }
        if (const auto it = elastic_of.find(f.entity); it != elastic_of.end()) {
            const auto& rest = r.get<StemRestShape>(f.entity);
            const auto& springs = r.get<StemSprings>(f.entity);
            fs.elastic_j = it->second;
            const double half_turn = glm::pi<double>();
            for (const double k : springs.hinge_nm_per_rad) fs.elastic_ceiling_j += 0.5 * k * half_turn * half_turn;
            for (std::size_t i = 0; i < springs.axial_n_per_m.size() && i < rest.segment_length_m.size(); ++i) {
                const double stretch = 0.1 * rest.segment_length_m[i];
                fs.elastic_ceiling_j += 0.5 * springs.axial_n_per_m[i] * stretch * stretch;
            }
        }
        if (const auto* grip = r.try_get<KenzanGrip>(f.entity)) {
            fs.fallen = grip->fallen;
            fs.fall_reason = grip->fall_reason;
            fs.fell_at_s = static_cast<double>(grip->fell_at_us) * 1e-6;
            fs.yielded = grip->yielded;
            fs.yield_holding_nm = grip->yield_holding_nm;
            fs.yield_gravity_nm = grip->yield_gravity_nm;
        }
        s.flower_states.push_back(fs);
    }
    return s;
}

std::string format_summary(const WorldSummary& s, double seconds) {
    char buffer[1024];
    std::snprintf(buffer, sizeof buffer,
                  "simulated %.3f s\n"
                  "flowers: %zu\n"
                  "parts: %zu active, %zu passive, %zu inactive\n"
                  "kenzan pins: %zu, hands: %zu\n"
                  "contacts: %zu\n"
                  "energy: kinetic %.6g J, elastic %.6g J, gravitational %.6g J (total %.6g J)\n"
                  "highest stem point: %.1f mm\n"
                  "frames handed to the main lane: %llu\n",
                  seconds, s.flowers, s.active_parts, s.passive_parts, s.inactive_parts, s.kenzan_pins, s.hands,
                  s.contacts, s.kinetic_j, s.elastic_j, s.gravitational_j, s.kinetic_j + s.elastic_j + s.gravitational_j,
                  s.highest_point_m * 1e3, static_cast<unsigned long long>(s.frames_received));
    std::string out = buffer;
    for (const auto& f : s.flower_states) {
        char line[512];
        if (f.in_kenzan) {
            // The verdict the physics reached: a fallen stem leans on more pins and may show a
            // positive margin now, so the moments when the pins first gave way are what explain it.
            char verdict[160];
            if (f.fallen && f.yielded && f.yield_gravity_nm <= f.yield_holding_nm) {
                // The pins first gave way to the stem's swing or spring after release, not to its weight.
                std::snprintf(verdict, sizeof verdict, "FELL at %.2f s: %s (the pins first gave way holding %.2f mN m as it swung after release, its weight asking %.2f)",
                              f.fell_at_s, components::fall_words(f.fall_reason), f.yield_holding_nm * 1e3, f.yield_gravity_nm * 1e3);
            } else if (f.fallen && f.yielded) {
                std::snprintf(verdict, sizeof verdict, "FELL at %.2f s: %s (the pins first gave way holding %.2f mN m under %.2f mN m)", f.fell_at_s,
                              components::fall_words(f.fall_reason),
                              f.yield_holding_nm * 1e3, f.yield_gravity_nm * 1e3);
            } else if (f.fallen) {
                std::snprintf(verdict, sizeof verdict, "FELL at %.2f s: %s", f.fell_at_s, components::fall_words(f.fall_reason));
            } else if (f.holding_moment_nm < f.gravity_moment_nm) {
                std::snprintf(verdict, sizeof verdict, "yielding (the pins hold less than its weight asks: it is tipping)");
            } else {
                std::snprintf(verdict, sizeof verdict, "stands");
            }
            std::snprintf(line, sizeof line,
                          "  %-14s in the kenzan: %zu pins, %.1f mm deep, resistance %.0f gf, holding %.2f mN m vs gravity %.2f mN m (margin %+.2f), insertions %u%s -> %s\n",
                          f.species.c_str(), f.pins, f.depth_m * 1e3, f.resistance_n / 9.80665e-3, f.holding_moment_nm * 1e3,
                          f.gravity_moment_nm * 1e3, (f.holding_moment_nm - f.gravity_moment_nm) * 1e3, f.insertions,
                          f.broken ? ", bottom broken" : "", verdict);
        } else {
            std::snprintf(line, sizeof line, "  %-14s not in the kenzan, insertions %u%s%s\n", f.species.c_str(), f.insertions,
                          f.broken ? ", bottom broken" : "", f.fallen ? ", fell" : "");
        }
        out += line;
    }
    for (const auto& f : s.flower_states) {
        if (f.elastic_j <= f.elastic_ceiling_j) continue;
        char line[400];
        std::snprintf(line, sizeof line,
                      "warning: %s's springs hold %.3g J, more than bending every joint half a turn would (%.3g J): the physics has left its "
                      "stable range (a haptic rate too low for it, or a hand moving too far in one tick)\n",
                      f.species.c_str(), f.elastic_j, f.elastic_ceiling_j);
        out += line;
    }
    return out;
}

std::string missing_covariate_sentence(const std::string& species, const systems::insertion::MissingCovariate& m) {
    char line[512];
    if (m.numeric) {
        std::snprintf(line, sizeof line,
                      "species '%s': its fitted extension reads '%s', which is not set: it is taken at %.4g, the centre of the range it was fitted on (%.4g to %.4g); set it with --env %s=VALUE",
                      species.c_str(), m.name.c_str(), m.value, m.low, m.high, m.name.c_str());
    } else {
        std::snprintf(line, sizeof line, "species '%s': its fitted extension reads '%s', which is not set: its reference level is used; set it with --env %s=LEVEL",
                      species.c_str(), m.name.c_str(), m.name.c_str());
    }
    return line;
}

std::vector<std::string> startup_warnings(World& w) {
    std::vector<std::string> out;
    const double haptic_hz = w.schedule.rates().hz("haptic");
    std::map<std::string, double> needed_hz;
    for (const auto& f : w.flowers) {
        const auto* points = w.sim.try_get<StemPoints>(f.entity);
        const auto* springs = w.sim.try_get<StemSprings>(f.entity);
        const auto* rest = w.sim.try_get<StemRestShape>(f.entity);
        if (!points || !springs || !rest) continue;
        double ring_hz = 0.0;
        for (std::size_t i = 0; i < springs->hinge_nm_per_rad.size(); ++i) {
            // Hinge i joins segments i and i+1 at point i+1: the lighter neighbour and the shorter lever ring fastest.
            const double m = std::min(points->mass_kg[i + 1], std::min(points->mass_kg[i], points->mass_kg[std::min(i + 2, points->mass_kg.size() - 1)]));
            const double l = std::min(rest->segment_length_m[i], rest->segment_length_m[std::min(i + 1, rest->segment_length_m.size() - 1)]);
            if (m > 0.0 && l > 0.0) ring_hz = std::max(ring_hz, std::sqrt(springs->hinge_nm_per_rad[i] / (m * l * l)) / (2.0 * glm::pi<double>()));
        }
        double& need = needed_hz[f.species];
        need = std::max(need, ring_hz / periods_per_step_limit);
    }
    for (const auto& [species, need] : needed_hz) {
        if (haptic_hz >= need) continue;
        char line[400];
        std::snprintf(line, sizeof line,
                      "warning: the haptic rate of %g Hz is below the %.0f Hz the %s's stiffness needs (its stem's joints ring at %.0f Hz); "
                      "its motion and whether it stands will be wrong",
                      haptic_hz, need, species.c_str(), need * periods_per_step_limit);
        out.emplace_back(line);
    }
    const auto* environment = w.sim.resource<const systems::insertion::Covariates>();
    std::set<std::string> said; // once per species
    for (const auto& f : w.flowers) {
        const auto* model = w.sim.try_get<PinResistance>(f.entity);
        if (!model || (model->extension.empty() && model->hold_extension.empty()) || !said.insert(f.species).second) continue;
        std::vector<components::DeteriorationTerm> terms = model->extension;
        terms.insert(terms.end(), model->hold_extension.begin(), model->hold_extension.end());
        for (const auto& m : systems::insertion::missing_covariates(terms, environment ? *environment : systems::insertion::Covariates{})) {
            out.push_back(missing_covariate_sentence(f.species, m));
        }
    }
    return out;
}

std::string format_realtime_report(const World& world, const std::vector<sched::LaneReport>& reports) {
    std::string out;
    char line[256];
    const auto& lanes = world.schedule.lanes();
    for (std::size_t i = 0; i < reports.size(); ++i) {
        const auto& w = reports[i].wake_lateness_ns;
        std::snprintf(line, sizeof line, "lane %-5s wake lateness: p50 %.1f us, p99 %.1f us, max %.1f us over %" PRIu64
                    " wake-ups; %" PRIu64 " catch-up clamps, %" PRIu64 " firings skipped\n",
                    lanes[i].name.c_str(), static_cast<double>(w.percentile(0.5)) / 1e3,
                    static_cast<double>(w.percentile(0.99)) / 1e3, static_cast<double>(w.max()) / 1e3, w.count(),
                    reports[i].clamp_events, reports[i].skipped_firings);
        out += line;
        if (lanes[i].thread == sched::LaneThread::own) {
            out += "lane " + lanes[i].name + " thread: " +
                   (reports[i].fifo_priority ? "real-time priority (SCHED_FIFO)\n" : "normal priority (no SCHED_FIFO: not permitted or not asked)\n");
        }
        const auto& t = reports[i].tick_ns;
        std::snprintf(line, sizeof line, "lane %-5s tick: p50 %.1f us, p99 %.1f us, max %.1f us; wake-ups later than 200 us: %.3f%%\n",
                    lanes[i].name.c_str(), static_cast<double>(t.percentile(0.5)) / 1e3, static_cast<double>(t.percentile(0.99)) / 1e3,
                    static_cast<double>(t.max()) / 1e3, 100.0 * w.fraction_above(200'000));
        out += line;
    }
    // The 1 kHz loop's own figure: the haptic-rate systems' lateness and missed deadlines.
    for (const auto& s : world.schedule.systems()) {
        if (s.desc.rate != "haptic") continue;
        const auto& l = s.stats.lateness_ns;
        std::snprintf(line, sizeof line, "1 kHz %-20s lateness: p50 %.1f us, p99 %.1f us, max %.1f us; missed %" PRIu64 " of %" PRIu64 "\n",
                    s.desc.name.c_str(), static_cast<double>(l.percentile(0.5)) / 1e3,
                    static_cast<double>(l.percentile(0.99)) / 1e3, static_cast<double>(l.max()) / 1e3,
                    s.stats.missed_deadlines, s.stats.calls);
        out += line;
    }
    if (!reports.empty()) {
        out += reports.front().memory_locked ? "memory: locked (mlockall: no page of the 1 kHz lane is swapped out)\n"
                                             : "memory: not locked (mlockall not asked, or not permitted: run as root or with CAP_IPC_LOCK)\n";
    }
    // Each device's own I/O thread (a HID transport's): at the real-time priority just below the
    // lane's when permitted; without it, the renderer's threads can hold a report past the DIY
    // firmware's 2 ms zeroing.
    for (std::size_t hand = 0; hand < 2; ++hand) {
        const auto* device = world.hand_devices[hand].get();
        if (!device) continue;
        const char* io = nullptr;
        switch (device->io_priority()) {
        case devices::IoPriority::none: break;
        case devices::IoPriority::realtime: io = "real-time priority (SCHED_FIFO), just below the 1 kHz lane's"; break;
        case devices::IoPriority::normal: io = "normal priority (as asked)"; break;
        case devices::IoPriority::not_permitted:
            io = "normal priority: SCHED_FIFO was not permitted (give the program CAP_SYS_NICE or an rtprio limit, docs/haptics.md)";
            break;
        }
        if (!io) continue;
        std::snprintf(line, sizeof line, "%s hand device I/O thread: %s\n", hand ? "right" : "left", io);
        out += line;
        const auto wire = device->wire();
        std::snprintf(line, sizeof line, "%s hand device reports: %" PRIu64 " queued, the last written was number %" PRIu64 "\n",
                      hand ? "right" : "left", wire.queued, wire.written);
        out += line;
    }
    return out;
}

} // namespace ikebana::game
