#pragma once

namespace ikebana::sched {

struct SystemDesc;
struct SystemContext;
class Schedule;
class DeterministicClock;
class RealtimeClock;
class DurationHistogram;
struct SystemStats;
template <typename T>
class TripleBuffer;

} // namespace ikebana::sched
