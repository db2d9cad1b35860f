// Issue 41's replay moments: the cost of keeping one (SessionPlayback::snapshot) and of going back to
// one (restore), in Sogetsu's scene halfway through its demonstration, and the memory each keeps
// (the heap's growth over 40 of them, reported as the counter `MB_each`).
// Run: build/release/tests/bench/replay_snapshot_bench
#include <benchmark/benchmark.h>

#include <filesystem>
#include <malloc.h>
#include <memory>
#include <vector>

#include "game/lesson/lesson.hpp"
#include "game/session/lesson_demo.hpp"
#include "game/session/lesson_session.hpp"

using namespace ikebana;
using namespace ikebana::game;

namespace {

// Bytes in use on the heap (glibc's count of allocated blocks, whatever was freed and reused before).
double heap_mb() { return static_cast<double>(mallinfo2().uordblks) / 1e6; }

// The Sogetsu demonstration on record (once), opened and played to its middle.
std::unique_ptr<SessionPlayback> halfway() {
    const auto dir = std::filesystem::temp_directory_path() / "ikebana_snapshot_bench";
    if (!std::filesystem::exists(dir / "session.json")) {
        auto lesson = load_lesson("sogetsu_basic_upright");
        DemoOptions options;
        options.record_dir = dir.string();
        if (!lesson || !run_lesson_demo(*lesson, options)) return nullptr;
    }
    auto p = SessionPlayback::open(dir);
    if (!p) return nullptr;
    (*p)->run_until((*p)->info().end_us / 2);
    return std::move(p).value();
}

void BM_KeepAMoment(benchmark::State& state) {
    auto p = halfway();
    if (!p) return state.SkipWithError("no recording");
    std::vector<std::shared_ptr<const PlaybackSnapshot>> kept;
    const double before = heap_mb();
    for (auto _ : state) {
        auto s = p->snapshot();
        if (!s) return state.SkipWithError(s.error().message.c_str());
        if (kept.size() < 40) kept.push_back(std::move(s).value());
    }
    state.counters["MB_each"] = (heap_mb() - before) / static_cast<double>(kept.size());
}
BENCHMARK(BM_KeepAMoment)->Unit(benchmark::kMillisecond);

void BM_GoBackToAMoment(benchmark::State& state) {
    auto p = halfway();
    if (!p) return state.SkipWithError("no recording");
    auto s = p->snapshot();
    if (!s) return state.SkipWithError(s.error().message.c_str());
    for (auto _ : state) {
        if (!p->restore(**s)) return state.SkipWithError("restore refused");
    }
}
BENCHMARK(BM_GoBackToAMoment)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
