// Persistent worker threads (bmWorkerPool.h): every task runs exactly once per Run, on a valid
// thread index, over many consecutive runs; Stop() joins cleanly and Run() then runs on the caller.
// RunRedoable: every task finishes at least once, the winner is a thread whose run finished, and
// the caller never waits for a worker that holds a task (a worker blocked in a task until the run
// has returned would otherwise deadlock the test).
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
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
      std::chrono::milliseconds(50)); // past the spin: workers sleep on the futex
  pool.Run(4, [&](int, int) { n.fetch_add(1); });
  EXPECT_EQ(n.load(), 8);
}

TEST(WorkerPool, RedoableRunsEveryTaskAndNamesAFinishedWinner) {
  for (int threads : {1, 2, 4}) {
    bm::WorkerPool pool(threads);
    pool.ReserveRedoable(1000);
    for (int tasks : {1, 2, 17, 1000}) {
      for (int round = 0; round < 50; ++round) {
        // finished[task * threads + thread]: that thread's run of the task finished.
        auto finished = std::make_shared<std::vector<std::atomic<int>>>(size_t(tasks * threads));
        pool.RunRedoable(tasks, std::make_shared<const bm::WorkerPool::RedoableFn>(
                                    [finished, threads](int task, int thread) {
                                      (*finished)[size_t(task * threads + thread)].store(1);
                                    }));
        for (int t = 0; t < tasks; ++t) {
          const int w = pool.Winner(t);
          ASSERT_GE(w, 0);
          ASSERT_LT(w, threads);
          ASSERT_EQ((*finished)[size_t(t * threads + w)].load(), 1) << "task " << t;
        }
      }
    }
  }
}

TEST(WorkerPool, RedoableNeverWaitsForABlockedWorker) {
  bm::WorkerPool pool(2);
  pool.ReserveRedoable(64);
  auto release = std::make_shared<std::atomic<bool>>(false);
  auto blocked = std::make_shared<std::atomic<int>>(-1); // the task a worker is held in
  for (int round = 0; round < 2000 && blocked->load() < 0; ++round) {
    pool.RunRedoable(64, std::make_shared<const bm::WorkerPool::RedoableFn>(
                             [release, blocked](int task, int thread) {
                               int none = -1;
                               if (thread != 0 && blocked->compare_exchange_strong(none, task))
                                 while (!release->load())
                                   std::this_thread::yield();
                             }));
    // Reaching here while a worker is held in a task: the caller ran that task itself.
    if (blocked->load() >= 0) {
      EXPECT_EQ(pool.Winner(blocked->load()), 0);
    }
  }
  // Later runs go on without the held worker.
  std::atomic<int> n{0};
  for (int round = 0; round < 10; ++round)
    pool.RunRedoable(64, std::make_shared<const bm::WorkerPool::RedoableFn>(
                             [&n](int, int thread) { n.fetch_add(thread == 0 ? 1 : 0); }));
  release->store(true);
  pool.Stop(); // joins the worker once it is let go
  EXPECT_GT(n.load(), 0);
}

// A run with more tasks right after a shorter one (the engine's frame: the removal's two tasks,
// then the next frame's pass): a worker still draining the short run must not claim a task of it
// past its end when it reads the new, larger task count before the new run is published. It would
// call the short run's function after that run returned (std::bad_function_call, or worse).
TEST(WorkerPool, AWorkerLateForARunNeverClaimsPastItsEnd) {
  bm::WorkerPool pool(2);
  pool.ReserveRedoable(256);
  std::atomic<int64_t> outOfRange{0}, ran{0};
  for (int round = 0; round < 20000; ++round) {
    pool.RunRedoable(256, std::make_shared<const bm::WorkerPool::RedoableFn>([](int, int) {}));
    const int tasks = 1 + round % 2;
    pool.Run(tasks, [&outOfRange, &ran, tasks](int task, int) {
      ran.fetch_add(1);
      if (task >= tasks)
        outOfRange.fetch_add(1);
    });
  }
  EXPECT_EQ(outOfRange.load(), 0);
  EXPECT_EQ(ran.load(), 30000);
}

TEST(WorkerPool, RefusesZeroThreads) {
  EXPECT_THROW(bm::WorkerPool(0), std::invalid_argument);
}

} // namespace
