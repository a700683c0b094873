// Persistent worker threads (bmWorkerPool.h): every task runs exactly once per Run, on a valid
// thread index, over many consecutive runs; Stop() joins cleanly and Run() then runs on the caller.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "bmWorkerPool.h"

namespace {

TEST(WorkerPool, EveryTaskRunsOnce) {
  for (int threads : {1, 2, 4}) {
    bm::WorkerPool pool(threads);
    EXPECT_EQ(pool.Threads(), threads);
    for (int tasks : {0, 1, 2, 3, 17, 1000}) {
      for (int round = 0; round < 50; ++round) {
        std::vector<std::atomic<int>> count(size_t(std::max(tasks, 1)));
        std::vector<std::atomic<int>> perThread(static_cast<size_t>(threads));
        pool.Run(tasks, [&](int task, int thread) {
          ASSERT_GE(thread, 0);
          ASSERT_LT(thread, threads);
          count[size_t(task)].fetch_add(1);
          perThread[size_t(thread)].fetch_add(1);
        });
        int total = 0;
        for (int t = 0; t < tasks; ++t)
          ASSERT_EQ(count[size_t(t)].load(), 1) << "task " << t << " of " << tasks;
        for (auto& p : perThread)
          total += p.load();
        ASSERT_EQ(total, tasks);
      }
    }
  }
}

TEST(WorkerPool, RunReturnsOnlyWhenAllWorkIsDone) {
  bm::WorkerPool pool(2);
  for (int round = 0; round < 200; ++round) {
    std::atomic<int> done{0};
    pool.Run(8, [&](int, int) {
      std::this_thread::yield();
      done.fetch_add(1);
    });
    ASSERT_EQ(done.load(), 8);
  }
}

TEST(WorkerPool, StopJoinsAndRunFallsBackToTheCaller) {
  bm::WorkerPool pool(3);
  std::atomic<int> n{0};
  pool.Run(10, [&](int, int) { n.fetch_add(1); });
  EXPECT_EQ(n.load(), 10);
  pool.Stop();
  EXPECT_EQ(pool.Threads(), 1);
  const auto caller = std::this_thread::get_id();
  pool.Run(5, [&](int, int thread) {
    EXPECT_EQ(thread, 0);
    EXPECT_EQ(std::this_thread::get_id(), caller);
    n.fetch_add(1);
  });
  EXPECT_EQ(n.load(), 15);
  pool.Stop(); // twice is fine; the destructor stops again
}

TEST(WorkerPool, IdleWorkersSleepAndWake) {
  bm::WorkerPool pool(2);
  std::atomic<int> n{0};
  pool.Run(4, [&](int, int) { n.fetch_add(1); });
  std::this_thread::sleep_for(
      std::chrono::milliseconds(50)); // past the spin: workers wait on the CV
  pool.Run(4, [&](int, int) { n.fetch_add(1); });
  EXPECT_EQ(n.load(), 8);
}

TEST(WorkerPool, RefusesZeroThreads) {
  EXPECT_THROW(bm::WorkerPool(0), std::invalid_argument);
}

} // namespace
