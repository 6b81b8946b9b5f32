// CpuTimedThread: the CPU time it reports is the thread's own, read while
// it runs and kept after it ends. A busy thread spins until its own clock
// shows 40 ms; a sleeping one uses (almost) none: CPU, not wall time.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "core/cpu_timed_thread.h"
#include "core/timing.h"

namespace dynslam {
namespace {

using namespace std::chrono_literals;

TEST(CpuTimedThread, ReportsTheThreadsOwnCpuTimeWhileItRunsAndAfter) {
  std::atomic<bool> spun{false}, release{false};
  double spun_ms = 0;
  CpuTimedThread t;
  EXPECT_EQ(t.cpuMs(), 0.0);  // not started
  t.start([&] {
    while (currentThreadCpuMs() < 40.0) {
    }
    spun_ms = currentThreadCpuMs();
    spun = true;
    while (!release) std::this_thread::sleep_for(1ms);
  });
  while (!spun) std::this_thread::sleep_for(1ms);
  const double running = t.cpuMs();  // read from outside while it waits
  EXPECT_GE(running, 40.0);
  release = true;
  t.join();
  const double after = t.cpuMs();
  EXPECT_GE(after, running);
  EXPECT_LT(after, spun_ms + 200.0);  // waiting in sleeps costs next to nothing
}

TEST(CpuTimedThread, ASleepingThreadUsesNextToNoCpu) {
  CpuTimedThread t;
  t.start([] { std::this_thread::sleep_for(150ms); });
  t.join();
  EXPECT_GE(t.cpuMs(), 0.0);
  EXPECT_LT(t.cpuMs(), 50.0);  // 150 ms of wall time, not of CPU
}

}  // namespace
}  // namespace dynslam
