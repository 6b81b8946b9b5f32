#pragma once
// Time and memory readings for the per-stage times and peak memory that run
// reports, export reports and benchmarks print: one monotonic clock and one
// definition of each reading, so every stage is measured the same way.
#include <chrono>
#include <ctime>

namespace dynslam {

using SteadyClock = std::chrono::steady_clock;

/// Milliseconds from a to b (steady clock).
inline double msBetween(SteadyClock::time_point a, SteadyClock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
/// Milliseconds since t0 (steady clock).
inline double msSince(SteadyClock::time_point t0) { return msBetween(t0, SteadyClock::now()); }
/// Seconds since t0 (steady clock).
inline double secondsSince(SteadyClock::time_point t0) {
  return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

/// Peak resident set size of this process so far, in MB (getrusage).
double peakRssMb();
/// User + system CPU time of this process so far (seconds, all threads):
/// on a shared machine wall times mostly measure the other jobs.
double processCpuSeconds();
/// The same in milliseconds (the micro-benchmarks' unit).
inline double processCpuMs() { return 1e3 * processCpuSeconds(); }
/// User + system CPU time (ms) of the calling thread so far.
double currentThreadCpuMs();
/// The reading (ms) of a CPU-time clock (CLOCK_PROCESS_CPUTIME_ID, a
/// thread's pthread_getcpuclockid); NaN when it cannot be read (the thread
/// has ended).
double cpuClockMs(clockid_t clock);

}  // namespace dynslam
