// WorkQueue: order, flush, stop and the thread-less mode. The
// sleeps only give a wrongly running worker time to show itself; no test
// depends on how fast anything runs.
#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "core/work_queue.h"

namespace dynslam {
namespace {

using namespace std::chrono_literals;

/// Records the items handled, in order, each after a short delay.
struct Recorder {
  std::mutex m;
  std::vector<int> seen;
  std::chrono::milliseconds delay{2};
  void operator()(int v) {
    std::this_thread::sleep_for(delay);
    std::lock_guard<std::mutex> lk(m);
    seen.push_back(v);
  }
  std::vector<int> get() {
    std::lock_guard<std::mutex> lk(m);
    return seen;
  }
};

TEST(WorkQueue, HandlesItemsInOrderAndFlushWaitsForTheLast) {
  Recorder rec;
  WorkQueue<int> q([&](int v) { rec(v); }, true);
  q.start();
  for (int i = 0; i < 10; ++i) q.push(i);
  q.flush();
  EXPECT_EQ(rec.get(), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_TRUE(q.idle());
  EXPECT_EQ(q.size(), 0u);
}

TEST(WorkQueue, StopHandlesWhatIsQueued) {
  Recorder rec;
  WorkQueue<int> q([&](int v) { rec(v); }, true);
  q.start();
  for (int i = 0; i < 3; ++i) q.push(i);
  q.stop();
  EXPECT_EQ(rec.get(), (std::vector<int>{0, 1, 2}));
  q.stop();  // a second stop is harmless
}

TEST(WorkQueue, WithoutAThreadItemsWaitForTryPop) {
  Recorder rec;
  WorkQueue<int> q([&](int v) { rec(v); }, false);
  q.start();  // no thread
  q.push(7);
  q.push(8);
  q.flush();  // returns at once
  std::this_thread::sleep_for(20ms);
  EXPECT_TRUE(rec.get().empty());
  EXPECT_EQ(q.size(), 2u);
  int v = 0;
  ASSERT_TRUE(q.tryPop(v));
  EXPECT_EQ(v, 7);
  ASSERT_TRUE(q.tryPop(v));
  EXPECT_EQ(v, 8);
  EXPECT_FALSE(q.tryPop(v));
  EXPECT_TRUE(q.idle());
}

}  // namespace
}  // namespace dynslam
