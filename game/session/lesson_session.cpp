#include "game/session/lesson_session.hpp"

#include <algorithm>
#include <cctype>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "engine/sched/clocks.hpp"
#include "game/asset_paths.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/scene/scene.hpp"
#include "game/world/world.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::game {

namespace {
constexpr const char* file_names[3] = {"left.csv", "right.csv", "commands.csv"};
// Four hours: a long class. A day was accepted once (a session.json that said so replayed for two
// hours); the hands are recorded only when they move, so a quiet end cannot be told from a lie by
// the samples, but not a lesson's length.
constexpr std::int64_t max_session_us = 4ll * 3600 * 1'000'000;
// A window session logs each camera turn it reads (a line a frame while the camera moves): two
// million is hours of turning at 60 frames a second.
constexpr std::size_t max_session_commands = 2'000'000;
constexpr std::uintmax_t max_hand_file_bytes = 512ull << 20; // a noisy position device: ~160 kB a second

std::string hex(std::uint64_t v) {
    char text[24];
    std::snprintf(text, sizeof text, "%016" PRIx64, v);
    return text;
}
} // namespace

Result<std::unique_ptr<SessionRecorder>> SessionRecorder::create(const std::filesystem::path& folder, bool real_time) {
    if (auto made = assets::create_output_folder(folder); !made) return std::move(made).error();
    auto recorder = std::unique_ptr<SessionRecorder>(new SessionRecorder());
    recorder->folder_ = folder;
    for (int i = 0; i < 3; ++i) {
        // Only the writers' threads touch these streams: the 1 kHz thread hands its lines to them.
        auto file = assets::open_output_stream(folder / file_names[i]);
        if (!file) return std::move(file).error();
        recorder->files_[i] = std::move(file).value();
    }
    const auto when_full = real_time ? AsyncLineWriter::WhenFull::drop : AsyncLineWriter::WhenFull::wait;
    for (int hand = 0; hand < 2; ++hand) recorder->recorders_[hand] = std::make_unique<devices::DeviceRecorder>(*recorder->files_[hand], when_full);
    recorder->commands_ = std::make_unique<AsyncLineWriter>(*recorder->files_[2], when_full);
    // Said at once (from the writer's thread), and again when the session ends.
    for (int i = 0; i < 3; ++i) {
        auto tell = [path = (folder / file_names[i]).string()](const std::string& why) {
            std::fprintf(stderr, "ikebana: the recording's %s: %s; it stops here\n", path.c_str(), why.c_str());
        };
        if (i < 2) recorder->recorders_[i]->on_failure(tell);
        else recorder->commands_->on_failure(tell);
    }
    return recorder;
}

void SessionRecorder::attach(World& world) {
    auto* slots = world.sim.resource<systems::HandDevices>();
    for (std::size_t hand = 0; hand < 2; ++hand) slots->record_to(hand, recorders_[hand].get());
    world.trainee.log = commands_.get();
    world.view.log = commands_.get();
    slots->note_events_to(commands_.get());
}

void SessionRecorder::detach(World& world) {
    auto* slots = world.sim.resource<systems::HandDevices>();
    for (std::size_t hand = 0; hand < 2; ++hand) slots->record_to(hand, nullptr);
    slots->note_events_to(nullptr);
    world.trainee.log = nullptr;
    world.view.log = nullptr;
}

Result<void> SessionRecorder::finish(const LessonDef& lesson, const std::string& kind, std::int64_t scored_us, std::int64_t end_us, double score,
                                     const World& world) {
    return write(lesson, kind, scored_us, end_us, score, world, nullptr);
}

Result<void> SessionRecorder::finish_window(const LessonDef& lesson, const std::string& kind, const WindowRun& run, std::int64_t end_us, double score,
                                            const World& world) {
    // The clock stood just past the scored frame when it was published.
    return write(lesson, kind, std::min(run.scored_frame_us + 1, end_us), end_us, score, world, &run);
}

std::uint64_t SessionRecorder::dropped() const { return recorders_[0]->dropped() + recorders_[1]->dropped() + commands_->dropped(); }

std::string SessionRecorder::failure() const {
    for (int i = 0; i < 2; ++i) {
        if (recorders_[i]->failed()) return std::string(file_names[i]) + ": " + recorders_[i]->failure();
    }
    if (commands_->failed()) return std::string(file_names[2]) + ": " + commands_->failure();
    return {};
}

Result<void> SessionRecorder::write(const LessonDef& lesson, const std::string& kind, std::int64_t scored_us, std::int64_t end_us, double score,
                                    const World& world, const WindowRun* window) {
    for (auto& r : recorders_) r->flush();
    commands_->flush();
    // A file the disk refused part of would not replay: no session.json makes it one.
    if (const std::string why = failure(); !why.empty()) {
        return make_error(ErrorCode::io_error, folder_.string() + ": not written whole (" + why + ")");
    }
    nlohmann::ordered_json j;
    j["format"] = "ikebana-session/1";
    // A shipped lesson by its id (the recording then replays on another checkout), another by a copy
    // in the recording's folder: a session names only files beside it or shipped ones (a session.json
    // is a file anyone may hand over, and once named any file on the machine).
    std::error_code ec;
    const bool shipped = !lesson.file.empty() && std::filesystem::equivalent(lesson.file.parent_path(), asset_dir() / "lessons", ec);
    if (lesson.file.empty() || shipped) {
        j["lesson"] = lesson.id;
    } else {
        auto text = assets::read_text_file(lesson.file);
        if (!text) return std::move(text).error();
        if (auto copied = assets::write_text_file(folder_ / "lesson.json", *text); !copied) return copied;
        j["lesson"] = "lesson.json";
    }
    j["kind"] = kind;
    j["scored_at_us"] = scored_us;
    j["end_us"] = end_us;
    j["score"] = score;
    // A window's main lane ran on the wall clock (its frames, its HUD): only the simulation replays.
    j["state_hash"] = hex(window ? world.sim.state_hash() : world.state_hash());
    nlohmann::ordered_json parts = nlohmann::ordered_json::object();
    for (const auto& [name, h] : world.sim.component_hashes()) parts["sim:" + name] = hex(h);
    if (!window) {
        for (const auto& [name, h] : world.main.component_hashes()) parts["main:" + name] = hex(h);
    }
    j["component_hashes"] = std::move(parts);
    if (window) {
        j["window"] = {{"scored_frame_us", window->scored_frame_us},
                       {"rates", window->rates},
                       {"env", window->env},
                       {"rate_device", {window->rate_device[0], window->rate_device[1]}}};
    }
    return assets::write_text_file(folder_ / "session.json", assets::json_text(j, 1) + "\n");
}

Result<SessionInfo> parse_session(std::string_view text, const std::string& label) {
    assets::JsonChecker c(label);
    const auto root = c.parse_object(text);
    if (!root) return c.error();
    SessionInfo info;
    (void)c.choice(*root, "", "format", {"ikebana-session/1"});
    const auto lesson = c.string(*root, "", "lesson");
    const auto kind = c.choice(*root, "", "kind", {"practice", "demonstration"});
    const auto scored = c.integer(*root, "", "scored_at_us", 0, max_session_us);
    const auto end = c.integer(*root, "", "end_us", 0, max_session_us);
    const auto score = c.number(*root, "", "score", {0.0, 100.0});
    const auto hash = c.string(*root, "", "state_hash");
    if (const auto* parts = c.object(*root, "", "component_hashes", false)) {
        for (const auto& [name, value] : parts->items()) {
            if (!value.is_string() || value.get<std::string>().size() != 16) c.problem("/component_hashes/" + name, "expected 16 hexadecimal digits");
            else info.component_hashes.emplace_back(name, value.get<std::string>());
        }
    }
    if (const auto* window = c.object(*root, "", "window", false)) {
        info.window = true;
        if (const auto frame = c.integer(*window, "/window", "scored_frame_us", 0, max_session_us)) info.scored_frame_us = *frame;
        for (const char* key : {"rates", "env"}) {
            const auto* list = c.array(*window, "/window", key, false);
            if (!list) continue;
            auto& into = std::string(key) == "rates" ? info.rates : info.env;
            for (std::size_t i = 0; i < list->size(); ++i) {
                if (!(*list)[i].is_string() || i >= 64) {
                    c.problem("/window/" + std::string(key) + "/" + std::to_string(i), "expected at most 64 texts name=value");
                    break; // one problem says it: a huge array must not make millions
                }
                into.push_back((*list)[i].get<std::string>());
            }
        }
        if (const auto* rate = c.array(*window, "/window", "rate_device", false)) {
            if (rate->size() != 2 || !(*rate)[0].is_boolean() || !(*rate)[1].is_boolean()) c.problem("/window/rate_device", "expected two booleans (left, right)");
            else for (int h = 0; h < 2; ++h) info.rate_device[h] = (*rate)[static_cast<std::size_t>(h)].get<bool>();
        }
        c.no_unknown_keys(*window, "/window", {"scored_frame_us", "rates", "env", "rate_device"});
    }
    c.no_unknown_keys(*root, "", {"format", "lesson", "kind", "scored_at_us", "end_us", "score", "state_hash", "component_hashes", "window"});
    if (hash) {
        char* stop = nullptr;
        info.state_hash = std::strtoull(hash->c_str(), &stop, 16);
        if (hash->size() != 16 || *stop != '\0' || !std::isxdigit(static_cast<unsigned char>(hash->front()))) c.problem("/state_hash", "expected 16 hexadecimal digits");
    }
    if (scored && end && *scored > *end) c.problem("/scored_at_us", "after /end_us");
    if (info.window && end && info.scored_frame_us >= *end) c.problem("/window/scored_frame_us", "not before /end_us");
    if (!c.ok()) return c.error();
    info.lesson = *lesson;
    info.kind = *kind;
    info.scored_us = *scored;
    info.end_us = *end;
    info.score = *score;
    return info;
}

Result<std::vector<SessionCommand>> parse_session_commands(std::string_view text, const std::string& label) {
    std::vector<SessionCommand> commands;
    std::size_t line_no = 0, from = 0;
    while (from < text.size()) {
        const std::size_t to = std::min(text.find('\n', from), text.size());
        const std::string line(text.substr(from, to - from));
        from = to + 1;
        ++line_no;
        if (line.empty()) continue;
        long long at = 0;
        unsigned hand = 0;
        double value = 0.0;
        char what[8] = {};
        int used = 0;
        const bool read = line.find('\0') == std::string::npos &&
                          std::sscanf(line.c_str(), "%18lld,%5[a-z],%1u,%24lf%n", &at, what, &hand, &value, &used) == 4 && used == static_cast<int>(line.size());
        const std::string kind = read ? what : "";
        SessionCommand c;
        c.at_us = at;
        c.value = value;
        bool fits = read && at >= 0 && at <= max_session_us && (commands.empty() || at >= commands.back().at_us) && std::isfinite(value);
        if (kind == "cut") {
            fits = fits && hand <= 1 && value > 0.0 && value < 100.0;
            c.command = systems::TraineeCommand{systems::TraineeCommand::Kind::cut, static_cast<std::uint8_t>(hand), value};
        } else if (kind == "prune") {
            fits = fits && hand <= 1 && value == 0.0;
            c.command = systems::TraineeCommand{systems::TraineeCommand::Kind::prune, static_cast<std::uint8_t>(hand), 0.0};
        } else if (kind == "view") {
            c.what = SessionCommand::What::view;
            fits = fits && hand == 0 && std::abs(value) < 1e6;
        } else if (kind == "gone" || kind == "back") {
            c.what = kind == "gone" ? SessionCommand::What::gone : SessionCommand::What::back;
            c.command.hand = static_cast<std::uint8_t>(hand);
            fits = fits && hand <= 1 && value == 0.0;
        } else if (kind == "skip") {
            c.what = SessionCommand::What::skip;
            fits = fits && hand == 0 && value > static_cast<double>(at) && value <= static_cast<double>(max_session_us) && value == std::floor(value);
        } else {
            fits = false;
        }
        if (!fits)
            return make_error(ErrorCode::parse_error, label + ": line " + std::to_string(line_no) +
                                                          ": expected time_us,cut,hand,keep_length_m (hand 0 or 1, a length in metres), time_us,prune,hand,0, time_us,view,0,yaw_rad or "
                                                          "time_us,skip,0,until_us, time_us,gone|back,hand,0, times in order");
        if (commands.size() >= max_session_commands) return make_error(ErrorCode::parse_error, label + ": line " + std::to_string(line_no) + ": more than " + std::to_string(max_session_commands) + " commands");
        commands.push_back(c);
    }
    return commands;
}

namespace {
// A recording's own files are read as files inside its folder: one that is a link leading out of it
// (to a secret, say, whose first cell an error message would then echo) is refused, as a data file's
// named files are (named_from).
Result<void> inside_recording(const std::filesystem::path& folder, const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::is_symlink(file, ec) || below(folder, file)) return {};
    return make_error(ErrorCode::invalid_argument, file.string() + ": a link that leads out of the recording's folder: its files are read only inside it");
}
} // namespace

Result<std::unique_ptr<SessionPlayback>> SessionPlayback::open(const std::filesystem::path& folder) {
    auto p = std::unique_ptr<SessionPlayback>(new SessionPlayback());
    p->session_file_ = folder / "session.json";
    const auto& session_file = p->session_file_;
    for (const char* name : {"session.json", "commands.csv", "left.csv", "right.csv"}) {
        if (auto inside = inside_recording(folder, folder / name); !inside) return inside.error();
    }
    auto text = assets::read_text_file(session_file);
    if (!text) return std::move(text).error();
    auto info = parse_session(*text, session_file.string());
    if (!info) return std::move(info).error();
    p->info_ = std::move(info).value();
    const bool by_id = p->info_.lesson.find('/') == std::string::npos && !p->info_.lesson.ends_with(".json");
    auto lesson_file = by_id ? Result<std::filesystem::path>(std::filesystem::path{}) : named_from(session_file, p->info_.lesson);
    if (!lesson_file) return make_error(lesson_file.error().code, session_file.string() + ": /lesson: " + lesson_file.error().message);
    auto lesson = by_id ? load_lesson(p->info_.lesson) : load_lesson_file(*lesson_file);
    if (!lesson) return make_error(lesson.error().code, session_file.string() + ": /lesson: " + lesson.error().message);
    p->lesson_ = std::move(lesson).value();
    auto scene = scene_for_lesson(p->lesson_);
    if (!scene) return std::move(scene).error();
    if (auto env = apply_environment_overrides(scene->environment, p->info_.env); !env)
        return make_error(env.error().code, session_file.string() + ": /window/env: " + env.error().message);
    p->sample_ = scene->sample;
    p->display_ = scene->display;
    auto footprint = footprint_of(p->lesson_);
    if (!footprint) return std::move(footprint).error();
    p->footprint_ = *footprint;
    const auto commands_file = folder / "commands.csv";
    auto lines = assets::read_text_file(commands_file);
    if (!lines) return std::move(lines).error();
    auto commands = parse_session_commands(*lines, commands_file.string());
    if (!commands) return std::move(commands).error();
    p->commands_ = std::move(commands).value();

    auto world = World::create(*scene, WorldOptions{.rate_overrides = p->info_.rates, .force_scheme = {}, .main_lane_systems = {}});
    if (!world) return make_error(world.error().code, session_file.string() + ": " + world.error().message);
    p->world_ = std::move(world).value();
    World& w = *p->world_;
    for (std::uint8_t hand = 0; hand < 2; ++hand) {
        const auto file = folder / file_names[hand];
        // A hand with no device in the session has its header alone.
        auto samples = assets::read_text_file(file, max_hand_file_bytes);
        if (!samples) return std::move(samples).error();
        if (std::count(samples->begin(), samples->end(), '\n') <= 1) continue;
        auto keys = devices::load_trajectory(file, max_hand_file_bytes);
        if (!keys) return std::move(keys).error();
        if (keys->empty()) continue;
        p->samples_[hand] = *keys;
        auto device = std::make_unique<devices::ScriptedDevice>(std::move(keys).value(), devices::ScriptedDevice::Mode::replay, "replay:" + file.string());
        // Away when the session's device was: from each `gone` to the next `back` (or the end).
        std::vector<std::pair<std::int64_t, std::int64_t>> away;
        for (const auto& c : p->commands_) {
            if (c.command.hand != hand) continue;
            if (c.what == SessionCommand::What::gone && (away.empty() || away.back().second != std::numeric_limits<std::int64_t>::max()))
                away.emplace_back(c.at_us, std::numeric_limits<std::int64_t>::max());
            if (c.what == SessionCommand::What::back && !away.empty() && away.back().second == std::numeric_limits<std::int64_t>::max()) away.back().second = c.at_us;
        }
        device->away(std::move(away));
        if (p->info_.rate_device[hand]) device->report_pushes(); // a SpaceMouse's samples are pushes, integrated again
        w.attach_device(hand, std::move(device));
    }
    for (std::size_t i = 0; i < w.schedule.lanes().size(); ++i) {
        if (w.schedule.lanes()[i].name == "sim") p->sim_lane_ = i;
    }
    p->clock_ = std::make_unique<sched::DeterministicClock>(w.schedule);
    return p;
}

SessionPlayback::~SessionPlayback() = default;

struct PlaybackSnapshot {
    std::string recording; // session.json's path: a snapshot goes back only into its own recording
    ecs::SavedRegistry sim, main;
    sched::DeterministicClock::Moment moment;
    sched::TripleBuffer<components::FrameSnapshot>::Copy frames;
    bool received = false; // the main lane had received a frame (ReceivedFrames::current was set)
    double yaw_rad = 0.0, logged_yaw_rad = 0.0;
    std::size_t next_command = 0;
};

Result<std::shared_ptr<const PlaybackSnapshot>> SessionPlayback::snapshot() const {
    const std::int64_t now = clock_->now_us();
    for (std::size_t i = next_; i > 0 && commands_[i - 1].at_us >= now; --i) {
        if (commands_[i - 1].what == SessionCommand::What::cut)
            return make_error(ErrorCode::invalid_argument, session_file_.string() + ": a cut given at " + std::to_string(now) + " us waits for its tick");
    }
    auto s = std::make_shared<PlaybackSnapshot>();
    s->recording = session_file_.string();
    auto sim = world_->sim.save();
    if (!sim) return std::move(sim).error();
    auto main = world_->main.save();
    if (!main) return std::move(main).error();
    s->sim = std::move(sim).value();
    s->main = std::move(main).value();
    s->moment = clock_->moment();
    s->frames = world_->channel.buffer.copy();
    const auto* received = world_->main.resource<const systems::ReceivedFrames>();
    s->received = received && received->current;
    s->yaw_rad = world_->view.yaw_rad.load();
    s->logged_yaw_rad = world_->view.logged_yaw_rad;
    s->next_command = next_;
    return std::shared_ptr<const PlaybackSnapshot>(std::move(s));
}

Result<void> SessionPlayback::restore(const PlaybackSnapshot& s) {
    if (s.recording != session_file_.string())
        return make_error(ErrorCode::invalid_argument, session_file_.string() + ": a moment of another recording (" + s.recording + ")");
    if (s.moment.firings.size() != world_->schedule.systems().size())
        return make_error(ErrorCode::invalid_argument, session_file_.string() + ": a moment of another schedule");
    // Every copy first (an allocation that fails changes nothing), then put in all at once.
    auto sim = world_->sim.stage_restore(s.sim);
    auto main = world_->main.stage_restore(s.main);
    auto frames = s.frames;
    world_->sim.commit_restore(std::move(sim));
    world_->main.commit_restore(std::move(main));
    world_->channel.buffer.take(std::move(frames));
    (void)clock_->resume_from(s.moment);
    // The writer's note of which flower's parts each slot holds was about the slots it wrote itself.
    world_->channel.writer.slots.clear();
    world_->channel.writer.parts_in_slot.clear();
    if (auto* received = world_->main.resource<systems::ReceivedFrames>()) received->current = s.received ? &world_->channel.buffer.read_buffer() : nullptr;
    world_->view.yaw_rad.store(s.yaw_rad);
    world_->view.logged_yaw_rad = s.logged_yaw_rad;
    systems::TraineeCommand waiting;
    while (world_->trainee.pop(waiting)) {} // a cut given here and not yet taken belongs to the moment left
    next_ = s.next_command;
    return {};
}

std::int64_t SessionPlayback::now_us() const { return clock_->now_us(); }

void SessionPlayback::run_until(std::int64_t t_us) {
    for (; next_ < commands_.size() && commands_[next_].at_us <= t_us; ++next_) {
        const SessionCommand& c = commands_[next_];
        clock_->run_until(c.at_us); // the ticks before it; the one at its time takes it
        switch (c.what) {
        case SessionCommand::What::cut: (void)world_->trainee.push(c.command); break; // one at a time: the ring never fills
        case SessionCommand::What::view: world_->view.yaw_rad.store(c.value); break;
        case SessionCommand::What::skip: clock_->skip_lane(sim_lane_, static_cast<std::int64_t>(c.value)); break;
        case SessionCommand::What::gone:
        case SessionCommand::What::back: break; // the replay's device knows (ScriptedDevice::away)
        }
    }
    clock_->run_until(t_us); // the ticks before it, as the recording's clock stood then
}

// A window session was scored on the frame the simulation had published then; a headless one on the
// frame its main lane had received.
Result<const components::FrameSnapshot*> SessionPlayback::scored_frame() {
    if (!info_.window) return &world_->main.resource<const systems::ReceivedFrames>()->latest();
    world_->channel.buffer.update();
    const components::FrameSnapshot* frame = &world_->channel.buffer.read_buffer();
    if (frame->sim_time_us != info_.scored_frame_us)
        return make_error(ErrorCode::parse_error, session_file_.string() + ": /window/scored_frame_us: no frame was published at " +
                                                      std::to_string(info_.scored_frame_us) + " us (the last was at " + std::to_string(frame->sim_time_us) + " us)");
    return frame;
}

Result<FormScore> SessionPlayback::score(const components::FrameSnapshot& frame) const {
    if (lesson_.scoring == "form") return score_form(lesson_, measure_arrangement(frame), footprint_, "replay");
    return score_sample(lesson_, measure_arrangement(frame), sample_);
}

std::uint64_t SessionPlayback::state_hash() const { return info_.window ? world_->sim.state_hash() : world_->state_hash(); }

Result<ReplayResult> replay_lesson_session(const std::filesystem::path& folder, const std::function<void(double, double)>& progress) {
    auto opened = SessionPlayback::open(folder);
    if (!opened) return std::move(opened).error();
    SessionPlayback& p = **opened;
    const SessionInfo& info = p.info();
    // A second at a time, so that a long session says how far it is.
    const auto run_to = [&](std::int64_t t_us) {
        while (p.now_us() < t_us) {
            p.run_until(std::min(t_us, (p.now_us() / 1'000'000 + 1) * 1'000'000));
            if (progress) progress(static_cast<double>(p.now_us()) * 1e-6, static_cast<double>(info.end_us) * 1e-6);
        }
    };
    run_to(info.scored_us);
    auto frame = p.scored_frame();
    if (!frame) return std::move(frame).error();
    auto scored_form = p.score(**frame);
    if (!scored_form) return std::move(scored_form).error();
    run_to(info.end_us);
    ReplayResult result;
    result.score = std::move(scored_form).value();
    result.state_hash = p.state_hash();
    const World& w = p.world();
    if (!info.component_hashes.empty() && result.state_hash != info.state_hash) {
        std::vector<std::pair<std::string, std::uint64_t>> now;
        for (const auto& [name, h] : w.sim.component_hashes()) now.emplace_back("sim:" + name, h);
        if (!info.window) {
            for (const auto& [name, h] : w.main.component_hashes()) now.emplace_back("main:" + name, h);
        }
        for (const auto& part : now) { // (not a structured binding: clang 14 cannot capture one in a lambda)
            const auto it = std::find_if(info.component_hashes.begin(), info.component_hashes.end(), [&](const auto& q) { return q.first == part.first; });
            if (it == info.component_hashes.end() || it->second != hex(part.second)) result.parted.push_back(part.first);
        }
    }
    result.recorded_state_hash = info.state_hash;
    result.recorded_score = info.score;
    result.kind = info.kind;
    result.seconds = static_cast<double>(p.now_us()) * 1e-6;
    return result;
}

} // namespace ikebana::game
