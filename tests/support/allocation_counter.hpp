#pragma once
// Counts heap allocations (operator new, every form) made while a given lane's systems run on the
// calling thread (sched::running_lane()): "nothing on the 1 kHz lane allocates" as a test can see it.
// Link allocation_counter.cpp into a test executable of its own: it replaces the global operator new.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>

namespace ikebana::test {

// Starts counting the allocations made while `lane` runs, from zero; nullptr stops (the count stays).
void count_allocations_in_lane(const char* lane);
// The same, counting only while one of `systems` (up to four names) runs or its queued changes are applied.
void count_allocations_in_systems(const char* lane, std::initializer_list<const char*> systems);
[[nodiscard]] std::uint64_t allocations_counted();
// Where the first few counted allocations came from, one frame a line (empty when none were counted).
[[nodiscard]] std::string where_allocations_came_from();

} // namespace ikebana::test
