// An exception in a worker thread (the local mapper's and loop closer's
// WorkQueue, the detector thread, the frame prefetcher: all through
// WorkerError) reaches the owner's thread instead of std::terminate. There is
// no bad input that makes those threads throw on demand, so these cases run
// the shared mechanism directly: without it this executable would abort.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>

#include "core/errors.h"
#include "core/work_queue.h"
#include "core/worker_error.h"

using namespace dynslam;

TEST(WorkerErrors, WorkQueueFlushRethrowsTheHandlersException) {
  std::atomic<int> handled{0};
  WorkQueue<int> q(
      [&](int i) {
        if (i == 2) throw InputError("frame.png", "cannot decode");
        ++handled;
      },
      true);
  q.start();
  for (int i = 0; i < 3; ++i) q.push(i);
  try {
    q.flush();
    FAIL() << "flush did not rethrow";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "frame.png");
  }
  EXPECT_EQ(handled.load(), 2);         // item 3 was dropped after the failure
  EXPECT_THROW(q.push(4), InputError);  // a failed worker stays failed
  EXPECT_THROW(q.rethrowIfFailed(), InputError);
}  // the destructor joins the worker without terminating

TEST(WorkerErrors, StopAfterAFailureDoesNotTerminate) {
  WorkQueue<int> q([](int) { throw std::runtime_error("boom"); }, true);
  q.start();
  q.push(1);
  q.stop();
  EXPECT_THROW(q.rethrowIfFailed(), std::runtime_error);
}

TEST(WorkerErrors, WorkerErrorKeepsTheFirstException) {
  WorkerError e;
  EXPECT_TRUE(e.run([] {}));
  EXPECT_FALSE(e.failed());
  std::thread t([&] {
    e.run([] { throw std::runtime_error("first"); });
    e.run([] { throw std::runtime_error("second"); });
  });
  t.join();
  ASSERT_TRUE(e.failed());
  try {
    e.rethrowIfFailed();
    FAIL();
  } catch (const std::runtime_error& x) {
    EXPECT_STREQ(x.what(), "first");
  }
}
