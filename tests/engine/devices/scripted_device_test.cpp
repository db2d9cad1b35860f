#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>
#include <random>
#include <sstream>

#include "engine/assets/files.hpp"
#include "engine/devices/scripted_device.hpp"
#include "tests/support/slow_stream.hpp"

using namespace ikebana;
using namespace ikebana::devices;
using ikebana::AsyncLineWriter;
using ikebana::test::SlowStream;

namespace {
const char* trajectory = "# a push down and a grab\n"
                         "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n"
                         "0.0,0.00,0.00,0.10,0,0,0,0\n"
                         "0.5,0.02,0.00,0.05,0,0,0.2,1\n"
                         "1.0,0.02,0.00,0.05,0,0,0.2,0\n";
}

TEST(ScriptedDevice, InterpolatesPosesAndStepsButtons) {
    auto keys = parse_trajectory(trajectory, "t.csv");
    ASSERT_TRUE(keys) << keys.error().message;
    ScriptedDevice device(std::move(keys).value(), ScriptedDevice::Mode::interpolate);
    const auto mid = device.poll(250'000);
    ASSERT_TRUE(mid);
    EXPECT_NEAR(mid->position.x, 0.01, 1e-12);
    EXPECT_NEAR(mid->position.z, 0.075, 1e-12);
    EXPECT_NEAR(mid->rotation.z, 0.1, 1e-12);
    EXPECT_EQ(mid->buttons, 0u) << "the grab begins at 0.5 s, not half-way to it";
    EXPECT_EQ(device.poll(600'000)->buttons, 1u);
    EXPECT_EQ(device.poll(5'000'000)->buttons, 0u);
    EXPECT_NEAR(device.poll(5'000'000)->position.z, 0.05, 1e-12) << "holds the last pose";
}

TEST(ScriptedDevice, BadFilesNameLineAndColumn) {
    const auto missing_header = parse_trajectory("0,0,0,0,0,0,0,0\n", "a.csv");
    ASSERT_FALSE(missing_header);
    EXPECT_NE(missing_header.error().message.find("a.csv:1:1: expected the header"), std::string::npos);
    const auto bad_number = parse_trajectory("time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n0.1,0,zero,0,0,0,0,0\n", "b.csv");
    ASSERT_FALSE(bad_number);
    EXPECT_NE(bad_number.error().message.find("b.csv:2:7: 'zero' is not a finite number"), std::string::npos) << bad_number.error().message;
    const auto backwards = parse_trajectory("time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n1,0,0,0,0,0,0,0\n0.5,0,0,0,0,0,0,0\n", "c.csv");
    ASSERT_FALSE(backwards);
    EXPECT_NE(backwards.error().message.find("c.csv:3:1: time must increase"), std::string::npos);
    const auto fields = parse_trajectory("time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n1,0,0,0,0,0,0,0,9\n", "d.csv");
    ASSERT_FALSE(fields);
    EXPECT_NE(fields.error().message.find("expected 8 fields, found 9"), std::string::npos);
    // A row of a million commas is counted, not split into a million cells first.
    const auto wide = parse_trajectory("time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons\n" + std::string(1'000'000, ',') + "\n", "w.csv");
    ASSERT_FALSE(wide);
    EXPECT_EQ(wide.error().message, "w.csv:2:1: expected 8 fields, found 1000001");
    EXPECT_FALSE(parse_trajectory("", "e.csv"));
    EXPECT_FALSE(load_trajectory("/nonexistent.csv"));
}

// Recording every sample and replaying it gives back exactly the same samples, bit for bit.
TEST(ScriptedDevice, RecordedSessionReplaysExactly) {
    ScriptedDevice source(*parse_trajectory(trajectory, "t.csv"), ScriptedDevice::Mode::interpolate);
    std::ostringstream file;
    DeviceRecorder recorder(file, AsyncLineWriter::WhenFull::wait);
    std::vector<DeviceSample> recorded;
    for (std::int64_t t = 0; t <= 1'000'000; t += 1000) {
        recorded.push_back(*source.poll(t));
        recorder.record(recorded.back());
    }
    recorder.flush();
    const auto keys = parse_trajectory(file.str(), "session.csv");
    ASSERT_TRUE(keys) << keys.error().message;
    ScriptedDevice replay(*keys, ScriptedDevice::Mode::replay);
    for (const auto& r : recorded) {
        const auto s = replay.poll(r.time_us);
        ASSERT_EQ(s->position, r.position) << r.time_us;
        ASSERT_EQ(s->rotation, r.rotation);
        ASSERT_EQ(s->buttons, r.buttons);
    }
}

// A mouse's hand stands still most of the time: a sample like the last is not written again, and
// the replay, which holds each sample until the next, still reads at every tick what was read.
TEST(ScriptedDevice, ASampleLikeTheLastIsNotWrittenAgainAndTheReplayReadsItAllTheSame) {
    std::ostringstream file;
    DeviceRecorder recorder(file, AsyncLineWriter::WhenFull::wait);
    std::vector<DeviceSample> recorded;
    for (std::int64_t t = 0; t < 3000'000; t += 1000) {
        const double x = t < 1'000'000 ? 0.0 : t < 1'500'000 ? 1e-6 * static_cast<double>(t) : 0.5; // still, moving, still
        recorded.push_back(DeviceSample{t, {x, 0.1, 0.2}, {0.0, 0.0, t >= 2'000'000 ? 0.3 : 0.0}, t >= 2'500'000 ? 1u : 0u});
        recorder.record(recorded.back());
    }
    recorder.flush();
    const std::string text = file.str();
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 1 + 500 + 1 + 1 + 1) << "the header, the first, the moving half second, the stop, the turn, the press";
    const auto keys = parse_trajectory(text, "still.csv");
    ASSERT_TRUE(keys) << keys.error().message;
    ScriptedDevice replay(*keys, ScriptedDevice::Mode::replay);
    for (const auto& r : recorded) {
        const auto s = replay.poll(r.time_us);
        ASSERT_EQ(s->position, r.position) << r.time_us;
        ASSERT_EQ(s->rotation, r.rotation) << r.time_us;
        ASSERT_EQ(s->buttons, r.buttons) << r.time_us;
    }
}

TEST(ScriptedDevice, MutatedFilesNeverCrashTheParser) {
    std::mt19937_64 rng(11);
    const std::string original = trajectory;
    const std::string alphabet = "0123456789.,-e\n#abc ";
    for (int i = 0; i < 5000; ++i) {
        std::string text = original;
        for (int k = 0; k < 3 && !text.empty(); ++k) {
            const auto at = rng() % text.size();
            if (rng() % 2) text[at] = alphabet[rng() % alphabet.size()];
            else text.erase(at, 1 + rng() % 3);
        }
        const auto keys = parse_trajectory(text, "m.csv");
        if (keys) {
            for (std::size_t j = 1; j < keys->size(); ++j) ASSERT_GT((*keys)[j].time_s, (*keys)[j - 1].time_s);
        } else {
            ASSERT_EQ(keys.error().message.rfind("m.csv", 0), 0u);
        }
    }
}

// `sim --record` once left empty CSVs after a crash: everything sat in the stream's buffer. The
// recorder's writer thread flushes what it has every 100 ms of wall time, so a recording still open
// (as at a crash) is on disk but for its last moments.
TEST(ScriptedDevice, ARecordingReachesTheDiskAsItGoes) {
    const auto path = std::filesystem::temp_directory_path() / "ikebana_recording_as_it_goes.csv";
    std::filesystem::remove(path);
    auto out = assets::open_output_stream(path);
    ASSERT_TRUE(out) << out.error().message;
    const auto on_disk = [&] { return assets::read_text_file(path).value(); };
    const auto lines_on_disk = [&] {
        const auto text = on_disk();
        return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
    };
    {
        DeviceRecorder recorder(**out, AsyncLineWriter::WhenFull::wait);
        for (std::int64_t t = 0; t <= 250'000; t += 1'000) recorder.record(DeviceSample{t, {0.1, 0.2, 0.3 + 1e-6 * static_cast<double>(t)}, {0, 0, 0}, 1});
        // Nobody flushes: within a few of the writer's periods it is there all the same.
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (lines_on_disk() < 1u + 251u && std::chrono::steady_clock::now() < give_up) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        EXPECT_EQ(lines_on_disk(), 1u + 251u) << "the header and every sample, with the recorder still open";
    }
    out->reset();
    EXPECT_EQ(lines_on_disk(), 1u + 251u) << "and all of it once closed";
}

// The 1 kHz thread hands its lines over and goes on: a stream that takes 200 ms for every write does
// not hold record() up. (Before, the recorder flushed the stream itself on the caller's thread.)
TEST(ScriptedDevice, RecordingOntoASlowStreamNeverHoldsTheCaller) {
    SlowStream slow(std::chrono::milliseconds(200));
    DeviceRecorder recorder(slow.stream, AsyncLineWriter::WhenFull::drop);
    std::int64_t worst_us = 0;
    for (std::int64_t t = 0; t < 300'000; t += 1'000) {
        const auto before = std::chrono::steady_clock::now();
        recorder.record(DeviceSample{t, {1e-6 * static_cast<double>(t), 0.0, 0.0}, {0, 0, 0}, 0});
        worst_us = std::max<std::int64_t>(worst_us, std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - before).count());
    }
    // A bound far from the stream's 200 ms, not a timing target: a sanitizer build on a busy machine
    // may take a millisecond now and then.
    EXPECT_LT(worst_us, 50'000) << "record() waited for the stream";
    EXPECT_EQ(recorder.dropped(), 0u) << "300 lines fit in the ring";
    recorder.flush();
    const std::string text = slow.text();
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1 + 300) << "all of it reaches the stream in the end";
}
