#include "game/lesson/lesson_session.hpp"

#include <algorithm>
#include <cctype>
#include <cinttypes>
#include <cstdio>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"
#include "engine/sched/clocks.hpp"
#include "game/asset_paths.hpp"
#include "game/lesson/lesson_scene.hpp"
#include "game/world/world.hpp"
#include "systems/haptics/hand_devices.hpp"
#include "systems/presentation/frame_channel.hpp"

namespace ikebana::game {

namespace {
constexpr const char* file_names[3] = {"left.csv", "right.csv", "commands.csv"};
constexpr std::int64_t max_session_us = 24ll * 3600 * 1'000'000; // a day: longer is not a lesson
constexpr std::size_t max_session_commands = 100'000;

std::string hex(std::uint64_t v) {
    char text[24];
    std::snprintf(text, sizeof text, "%016" PRIx64, v);
    return text;
}
} // namespace

Result<std::unique_ptr<SessionRecorder>> SessionRecorder::create(const std::filesystem::path& folder) {
    if (auto made = assets::create_output_folder(folder); !made) return std::move(made).error();
    auto recorder = std::unique_ptr<SessionRecorder>(new SessionRecorder());
    recorder->folder_ = folder;
    for (int i = 0; i < 3; ++i) {
        auto file = assets::open_output_stream(folder / file_names[i]);
        if (!file) return std::move(file).error();
        recorder->files_[i] = std::move(file).value();
    }
    for (int hand = 0; hand < 2; ++hand) recorder->recorders_[hand] = std::make_unique<devices::DeviceRecorder>(*recorder->files_[hand]);
    return recorder;
}

void SessionRecorder::attach(World& world) {
    auto* slots = world.sim.resource<systems::HandDevices>();
    for (std::size_t hand = 0; hand < 2; ++hand) slots->recorder[hand] = recorders_[hand].get();
    world.trainee.log = files_[2].get();
}

Result<void> SessionRecorder::finish(const LessonDef& lesson, const std::string& kind, std::int64_t scored_us, std::int64_t end_us, double score,
                                     const World& world) {
    for (auto& f : files_) f->flush();
    nlohmann::ordered_json j;
    j["format"] = "ikebana-session/1";
    // A shipped lesson by its id (the recording then replays on another checkout), another by its file.
    std::error_code ec;
    const bool shipped = !lesson.file.empty() && std::filesystem::equivalent(lesson.file.parent_path(), asset_dir() / "lessons", ec);
    j["lesson"] = lesson.file.empty() || shipped ? lesson.id : std::filesystem::absolute(lesson.file).string();
    j["kind"] = kind;
    j["scored_at_us"] = scored_us;
    j["end_us"] = end_us;
    j["score"] = score;
    j["state_hash"] = hex(world.state_hash());
    nlohmann::ordered_json parts = nlohmann::ordered_json::object();
    for (const auto& [name, h] : world.sim.component_hashes()) parts["sim:" + name] = hex(h);
    for (const auto& [name, h] : world.main.component_hashes()) parts["main:" + name] = hex(h);
    j["component_hashes"] = std::move(parts);
    return assets::write_text_file(folder_ / "session.json", j.dump(1) + "\n");
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
    c.no_unknown_keys(*root, "", {"format", "lesson", "kind", "scored_at_us", "end_us", "score", "state_hash", "component_hashes"});
    if (hash) {
        char* stop = nullptr;
        info.state_hash = std::strtoull(hash->c_str(), &stop, 16);
        if (hash->size() != 16 || *stop != '\0' || !std::isxdigit(static_cast<unsigned char>(hash->front()))) c.problem("/state_hash", "expected 16 hexadecimal digits");
    }
    if (scored && end && *scored > *end) c.problem("/scored_at_us", "after /end_us");
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
        double keep = 0.0;
        char what[8] = {};
        int used = 0;
        const bool read = line.find('\0') == std::string::npos &&
                          std::sscanf(line.c_str(), "%18lld,%3[a-z],%1u,%24lf%n", &at, what, &hand, &keep, &used) == 4 && used == static_cast<int>(line.size());
        if (!read || std::string(what) != "cut" || hand > 1 || at < 0 || at > max_session_us || !(keep > 0.0 && keep < 100.0) ||
            (!commands.empty() && at < commands.back().at_us))
            return make_error(ErrorCode::parse_error, label + ": line " + std::to_string(line_no) +
                                                          ": expected time_us,cut,hand,keep_length_m (hand 0 or 1, times in order, a length in metres)");
        if (commands.size() >= max_session_commands) return make_error(ErrorCode::parse_error, label + ": line " + std::to_string(line_no) + ": more than " + std::to_string(max_session_commands) + " commands");
        commands.push_back({at, systems::TraineeCommand{systems::TraineeCommand::Kind::cut, static_cast<std::uint8_t>(hand), keep}});
    }
    return commands;
}

Result<ReplayResult> replay_lesson_session(const std::filesystem::path& folder) {
    const auto session_file = folder / "session.json";
    auto text = assets::read_text_file(session_file);
    if (!text) return std::move(text).error();
    auto info = parse_session(*text, session_file.string());
    if (!info) return std::move(info).error();
    auto lesson = load_lesson(info->lesson);
    if (!lesson) return make_error(lesson.error().code, session_file.string() + ": /lesson: " + lesson.error().message);
    auto scene = scene_for_lesson(*lesson);
    if (!scene) return std::move(scene).error();
    const auto footprint = footprint_of(*lesson);
    if (!footprint) return std::move(footprint).error();
    const auto commands_file = folder / "commands.csv";
    auto lines = assets::read_text_file(commands_file);
    if (!lines) return std::move(lines).error();
    auto commands = parse_session_commands(*lines, commands_file.string());
    if (!commands) return std::move(commands).error();

    auto world = World::create(*scene);
    if (!world) return std::move(world).error();
    World& w = **world;
    for (std::uint8_t hand = 0; hand < 2; ++hand) {
        const auto file = folder / file_names[hand];
        // A hand with no device in the session has its header alone.
        auto samples = assets::read_text_file(file);
        if (!samples) return std::move(samples).error();
        if (std::count(samples->begin(), samples->end(), '\n') <= 1) continue;
        auto keys = devices::load_trajectory(file);
        if (!keys) return std::move(keys).error();
        if (keys->empty()) continue;
        w.attach_device(hand, std::make_unique<devices::ScriptedDevice>(std::move(keys).value(), devices::ScriptedDevice::Mode::replay, "replay:" + file.string()));
    }
    sched::DeterministicClock clock(w.schedule);
    ReplayResult result;
    std::size_t next = 0;
    const auto run_commands_until = [&](std::int64_t t_us) {
        for (; next < commands->size() && (*commands)[next].at_us <= t_us; ++next) {
            clock.run_until((*commands)[next].at_us); // the ticks before it; the one at its time takes it
            w.trainee.push((*commands)[next].command);
        }
        clock.run_until(t_us); // the ticks before it, as the recording's clock stood then
    };
    run_commands_until(info->scored_us);
    auto scored_form = score_form(*lesson, measure_arrangement(w.main.resource<const systems::ReceivedFrames>()->latest()), *footprint, "replay");
    if (!scored_form) return std::move(scored_form).error();
    run_commands_until(info->end_us);
    result.score = std::move(scored_form).value();
    result.state_hash = w.state_hash();
    if (!info->component_hashes.empty() && result.state_hash != info->state_hash) {
        std::vector<std::pair<std::string, std::uint64_t>> now;
        for (const auto& [name, h] : w.sim.component_hashes()) now.emplace_back("sim:" + name, h);
        for (const auto& [name, h] : w.main.component_hashes()) now.emplace_back("main:" + name, h);
        for (const auto& part : now) { // (not a structured binding: clang 14 cannot capture one in a lambda)
            const auto it = std::find_if(info->component_hashes.begin(), info->component_hashes.end(), [&](const auto& p) { return p.first == part.first; });
            if (it == info->component_hashes.end() || it->second != hex(part.second)) result.parted.push_back(part.first);
        }
    }
    result.recorded_state_hash = info->state_hash;
    result.recorded_score = info->score;
    result.kind = info->kind;
    result.seconds = static_cast<double>(clock.now_us()) * 1e-6;
    return result;
}

} // namespace ikebana::game
