#pragma once
// A lesson session on record: every device sample of each hand (left.csv, right.csv, the format
// `replay:FILE` reads), every command the simulation took from the trainee (commands.csv: cuts, at
// the tick they were taken) and session.json (the lesson, when it was scored, when it ended, the
// score and the final state hash). `ikebana lesson replay DIR` plays it back on the deterministic
// clock and must reach the same score and the same state hash.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/core/async_line_writer.hpp"
#include "engine/core/result.hpp"
#include "engine/devices/scripted_device.hpp"
#include "game/training/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "game/world/lesson_scene.hpp"
#include "systems/haptics/trainee_command_system.hpp"

namespace ikebana::game {

class World;
}
namespace ikebana::sched {
class DeterministicClock;
}
namespace ikebana::components {
struct FrameSnapshot;
}
namespace ikebana::game {

class SessionRecorder {
public:
    // Makes the folder (refused if it is a file or a link; files in it are replaced whole at the end).
    // The 1 kHz thread writes its lines through rings (AsyncLineWriter); `real_time`: a ring the disk
    // fell seconds behind on drops and counts lines rather than hold the haptic loop; headless, the
    // simulation waits for room (it has no deadline, and the recording stays whole).
    static Result<std::unique_ptr<SessionRecorder>> create(const std::filesystem::path& folder, bool real_time);
    // Before the session runs (the hands' samples, the trainee's commands, the camera's turns).
    void attach(World& world);
    // After it, before the recorder goes: the world writes nothing more here.
    void detach(World& world);
    // After it: session.json. `scored_us` and `end_us` are the clock's times then (ticks before them had run).
    // The world's state hash goes with each component type's share of it, so that a replay that parts
    // can say where.
    Result<void> finish(const LessonDef& lesson, const std::string& kind, std::int64_t scored_us, std::int64_t end_us, double score, const World& world);
    // A window session's end (SessionInfo's window fields): `scored_frame_us` is the time of the frame
    // the score was taken from, `end_us` where the simulation's clock stood.
    struct WindowRun {
        std::int64_t scored_frame_us = 0;
        std::vector<std::string> rates, env;
        bool rate_device[2] = {false, false};
    };
    Result<void> finish_window(const LessonDef& lesson, const std::string& kind, const WindowRun& run, std::int64_t end_us, double score, const World& world);
    // The commands file (cuts, the camera's turns, the clock's skips), for a real-time clock's on_skip:
    // written from the simulation's thread only.
    [[nodiscard]] AsyncLineWriter& commands() { return *commands_; }
    // Lines the rings dropped (real time, the disk seconds behind): a replay would part.
    [[nodiscard]] std::uint64_t dropped() const;
    // A file the disk refused part of (full): "left.csv: No space left on device"; empty while whole.
    // Said on stderr the moment it happens; finish() then refuses to call the recording a session.
    [[nodiscard]] std::string failure() const;
    [[nodiscard]] const std::filesystem::path& folder() const { return folder_; }

private:
    Result<void> write(const LessonDef& lesson, const std::string& kind, std::int64_t scored_us, std::int64_t end_us, double score, const World& world,
                       const WindowRun* window);
    std::filesystem::path folder_;
    std::unique_ptr<std::ostream> files_[3]; // left, right, commands
    // After the files: they are stopped (and have written everything) before the files close.
    std::unique_ptr<devices::DeviceRecorder> recorders_[2];
    std::unique_ptr<AsyncLineWriter> commands_;
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
    // A window session (its main lane ran on the wall clock): the hash and the parts are the
    // simulation's alone, the score was taken from the frame the simulation published at
    // `scored_frame_us`, and the session ran with these rate and environment overrides.
    bool window = false;
    std::int64_t scored_frame_us = 0;
    std::vector<std::string> rates, env;
    bool rate_device[2] = {false, false}; // a hand's device reported a push (a SpaceMouse), not a place
};
// What the simulation took from outside, when (commands.csv's lines: time_us,WHAT,hand,value):
// - cut: the trainee's cut of what `hand` holds, value the length kept (m);
// - view: the camera's yaw the hands' workspace turned to (rad), hand 0;
// - skip: a window session's simulation fell behind and its clock dropped the firings from time_us
//   up to `value` (us), hand 0 (sched::RealtimeConfig::on_skip);
// - gone, back: `hand`'s device went away (a read failed, it was unplugged) and came back; value 0.
struct SessionCommand {
    enum class What : std::uint8_t { cut, view, skip, gone, back };
    std::int64_t at_us = 0;
    What what = What::cut;
    systems::TraineeCommand command; // cut
    double value = 0.0;              // view: yaw (rad); skip: where the firings resume (us)
};
// Readers of a session's own files; errors name `label` and the field or line.
Result<SessionInfo> parse_session(std::string_view text, const std::string& label);
Result<std::vector<SessionCommand>> parse_session_commands(std::string_view text, const std::string& label);

// A moment of a playback kept aside (SessionPlayback::snapshot): the world's two registries, the
// timeline, what stands in the channels between the lanes and how far the recording's commands have
// been given. Taken from one playback, it can be put back into any playback of the same recording.
struct PlaybackSnapshot;

// A recording set up to play: the lesson's world with the recorded hands, and what the simulation
// took from outside (cuts, the camera's turns, the clock's skips) given at the ticks it took them as
// the clock moves on. Never backwards: to go back, open it again (the window's scrubbing does).
class SessionPlayback {
public:
    // Errors name the file and line (session.json's fields, commands.csv's lines, the device files').
    static Result<std::unique_ptr<SessionPlayback>> open(const std::filesystem::path& folder);
    ~SessionPlayback();
    // Runs every firing before t_us.
    void run_until(std::int64_t t_us);
    [[nodiscard]] std::int64_t now_us() const;
    // The frame the recording was scored on, once the clock has reached info().scored_us.
    Result<const components::FrameSnapshot*> scored_frame();
    // A frame scored as the session scored it (the lesson's form, or free practice's sample).
    [[nodiscard]] Result<FormScore> score(const components::FrameSnapshot& frame) const;
    // The simulation's state hash (a window session's) or the whole world's (a headless one's).
    [[nodiscard]] std::uint64_t state_hash() const;
    // This moment, to come back to (the window's scrubbing: any point in a second or two, where playing
    // the recording again from its start took minutes). Refused at a tick a cut was given at and the
    // simulation has not yet taken: the next tick's moment will do.
    [[nodiscard]] Result<std::shared_ptr<const PlaybackSnapshot>> snapshot() const;
    // Back (or on) to `s`, taken from this playback or another of the same recording; refused, with
    // nothing changed, for another recording's.
    Result<void> restore(const PlaybackSnapshot& s);

    [[nodiscard]] World& world() { return *world_; }
    [[nodiscard]] const SessionInfo& info() const { return info_; }
    [[nodiscard]] const LessonDef& lesson() const { return lesson_; }
    [[nodiscard]] const DisplayDef& display() const { return display_; } // the lesson's camera and stereo
    [[nodiscard]] const KenzanFootprint& footprint() const { return footprint_; }
    [[nodiscard]] const std::vector<SessionCommand>& commands() const { return commands_; }
    // Each hand's recorded samples (empty: no device in that hand).
    [[nodiscard]] const std::vector<devices::Keyframe>& samples(std::size_t hand) const { return samples_[hand]; }

private:
    SessionPlayback() = default;
    std::filesystem::path session_file_;
    SessionInfo info_;
    LessonDef lesson_;
    std::vector<SampleStem> sample_;
    DisplayDef display_;
    KenzanFootprint footprint_;
    std::vector<SessionCommand> commands_;
    std::vector<devices::Keyframe> samples_[2];
    std::unique_ptr<World> world_;
    std::unique_ptr<sched::DeterministicClock> clock_;
    std::size_t sim_lane_ = 0;
    std::size_t next_ = 0;
};

// Plays a recording through to its end: the score at the recorded moment and the final state hash.
// `progress` is told the simulated seconds done and in all, every simulated second.
Result<ReplayResult> replay_lesson_session(const std::filesystem::path& folder, const std::function<void(double done_s, double of_s)>& progress = {});

} // namespace ikebana::game
