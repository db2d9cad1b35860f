#include "tests/support/allocation_counter.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <new>

#include <execinfo.h>

#include "engine/sched/clocks.hpp"

namespace ikebana::test {

namespace {

std::atomic<const char*> counted_lane{nullptr};
std::atomic<std::uint64_t> counted{0};
// Distinct places (by the trace's first frames), each with one trace and a count.
constexpr int kept_traces = 24;
constexpr int trace_depth = 16;
constexpr int site_frames = 6;
std::array<std::array<void*, trace_depth>, kept_traces> traces{};
std::array<int, kept_traces> trace_sizes{};
std::array<std::uint64_t, kept_traces> trace_counts{};
std::atomic<int> sites{0};
thread_local bool inside = false; // backtrace() may allocate the first time
std::array<std::atomic<const char*>, 4> counted_systems{}; // all null: every system of the lane

void note(std::size_t) noexcept {
    const char* lane = counted_lane.load(std::memory_order_relaxed);
    if (!lane || inside) return;
    const char* running = sched::running_lane();
    if (!running || std::strcmp(running, lane) != 0) return;
    if (counted_systems[0].load(std::memory_order_relaxed)) {
        const char* system = sched::running_system();
        bool listed = false;
        for (const auto& name : counted_systems) {
            const char* n = name.load(std::memory_order_relaxed);
            listed = listed || (n && system && std::strcmp(n, system) == 0);
        }
        if (!listed) return;
    }
    counted.fetch_add(1, std::memory_order_relaxed);
    inside = true;
    std::array<void*, trace_depth> trace{};
    const int size = backtrace(trace.data(), trace_depth);
    inside = false;
    const int known = sites.load();
    for (int i = 0; i < known; ++i) {
        if (std::equal(trace.begin(), trace.begin() + std::min(size, site_frames), traces[i].begin())) {
            ++trace_counts[i];
            return;
        }
    }
    if (known < kept_traces) {
        traces[known] = trace;
        trace_sizes[known] = size;
        trace_counts[known] = 1;
        sites.store(known + 1);
    }
}

void* allocate(std::size_t size, std::size_t alignment = 0) {
    note(size);
    void* p = nullptr;
    if (alignment > alignof(std::max_align_t)) {
        if (posix_memalign(&p, alignment, size ? size : 1) != 0) p = nullptr;
    } else {
        p = std::malloc(size ? size : 1);
    }
    if (!p) throw std::bad_alloc();
    return p;
}

} // namespace

void count_allocations_in_lane(const char* lane) {
    if (lane) {
        for (auto& name : counted_systems) name.store(nullptr);
        counted.store(0);
        trace_sizes.fill(0);
        trace_counts.fill(0);
        sites.store(0);
    }
    counted_lane.store(lane);
}

void count_allocations_in_systems(const char* lane, std::initializer_list<const char*> systems) {
    count_allocations_in_lane(lane);
    std::size_t i = 0;
    for (const char* name : systems) {
        if (i < counted_systems.size()) counted_systems[i++].store(name);
    }
}

std::uint64_t allocations_counted() { return counted.load(); }

std::string where_allocations_came_from() {
    std::string out;
    const int n = sites.load();
    for (int i = 0; i < n; ++i) {
        out += "allocation " + std::to_string(i + 1) + " (" + std::to_string(trace_counts[i]) + " times):\n";
        char** names = backtrace_symbols(traces[i].data(), trace_sizes[i]);
        for (int f = 0; f < trace_sizes[i]; ++f) out += std::string("  ") + (names ? names[f] : "?") + "\n";
        std::free(names);
    }
    return out;
}

} // namespace ikebana::test

void* operator new(std::size_t size) { return ikebana::test::allocate(size); }
void* operator new[](std::size_t size) { return ikebana::test::allocate(size); }
void* operator new(std::size_t size, std::align_val_t a) { return ikebana::test::allocate(size, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t size, std::align_val_t a) { return ikebana::test::allocate(size, static_cast<std::size_t>(a)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return ikebana::test::allocate(size);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return ikebana::test::allocate(size);
    } catch (...) {
        return nullptr;
    }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
