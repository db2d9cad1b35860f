#pragma once
// A lesson session on record: every device sample of each hand (left.csv, right.csv, the format
// `replay:FILE` reads), every command the simulation took from the trainee (commands.csv: cuts, at
// the tick they were taken) and session.json (the lesson, when it was scored, when it ended, the
// score and the final state hash). `ikebana lesson replay DIR` plays it back on the deterministic
// clock and must reach the same score and the same state hash.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/core/result.hpp"
#include "engine/devices/scripted_device.hpp"
#include "game/lesson/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "systems/haptics/trainee_command_system.hpp"

namespace ikebana::game {

class World;

class SessionRecorder {
public:
    // Makes the folder (refused if it is a file or a link; files in it are replaced whole at the end).
    static Result<std::unique_ptr<SessionRecorder>> create(const std::filesystem::path& folder);
    // Before the session runs.
    void attach(World& world);
    // After it: session.json. `scored_us` and `end_us` are the clock's times then (ticks before them had run).
    // The world's state hash goes with each component type's share of it, so that a replay that parts
    // can say where.
    Result<void> finish(const LessonDef& lesson, const std::string& kind, std::int64_t scored_us, std::int64_t end_us, double score, const World& world);

private:
    std::filesystem::path folder_;
    std::unique_ptr<std::ostream> files_[3]; // left, right, commands
    std::unique_ptr<devices::DeviceRecorder> recorders_[2];
};

struct ReplayResult {
    FormScore score;
    std::uint64_t state_hash = 0;
    std::uint64_t recorded_state_hash = 0;
    double recorded_score = 0.0;
    std::string kind;
    double seconds = 0.0;
    std::vector<std::string> parted; // component types whose state differs from the recording's
};

// session.json, read.
struct SessionInfo {
    std::string lesson; // id or file
    std::string kind;   // "practice" or "demonstration"
    std::int64_t scored_us = 0, end_us = 0;
    double score = 0.0;
    std::uint64_t state_hash = 0;
    std::vector<std::pair<std::string, std::string>> component_hashes; // "sim:components::StemPoints" -> hex
};
// A command the simulation took, when (commands.csv's lines: time_us,cut,hand,keep_length_m).
struct SessionCommand {
    std::int64_t at_us = 0;
    systems::TraineeCommand command;
};
// Readers of a session's own files; errors name `label` and the field or line.
Result<SessionInfo> parse_session(std::string_view text, const std::string& label);
Result<std::vector<SessionCommand>> parse_session_commands(std::string_view text, const std::string& label);

// Errors name the file and line (session.json's fields, commands.csv's lines, the device files').
Result<ReplayResult> replay_lesson_session(const std::filesystem::path& folder);

} // namespace ikebana::game
