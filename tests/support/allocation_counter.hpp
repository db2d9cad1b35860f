#pragma once
// Counts heap allocations (operator new, every form) made while a given lane's systems run on the
// calling thread (sched::running_lane()): "nothing on the 1 kHz lane allocates" as a test can see it.
// Link allocation_counter.cpp into a test executable of its own: it replaces the global operator new.
#include <cstddef>
#include <cstdint>
#include <string>

namespace ikebana::test {

// Starts counting the allocations made while `lane` runs, from zero; nullptr stops (the count stays).
void count_allocations_in_lane(const char* lane);
[[nodiscard]] std::uint64_t allocations_counted();
// Where the first few counted allocations came from, one frame a line (empty when none were counted).
[[nodiscard]] std::string where_allocations_came_from();

} // namespace ikebana::test
