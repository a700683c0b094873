// bmWorkerPool.h - persistent worker threads for the per-frame parallel loops.
//
// Threads are started once and joined in Stop() / the destructor: no thread is created per
// frame (that costs ~50 us and sometimes > 1 ms here). Run(n, fn) hands out task indices
// 0..n-1 through an atomic counter; the calling thread works too and returns when every task is
// done. Workers wait on a condition variable between runs (after a short spin), so they leave the
// cores to the render and GUI threads when the haptic loop idles. Run() is called from one thread
// at a time.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace bm {

class WorkerPool {
public:
  /// threads >= 1: total threads including the caller (threads - 1 workers are started).
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int Threads() const { return int(Workers_.size()) + 1; }
  /// Runs fn(task, thread) for task in [0, tasks); thread in [0, Threads()). Blocks until done.
  void Run(int tasks, const std::function<void(int task, int thread)>& fn);
  /// Stops and joins the workers; Run() afterwards runs on the caller alone.
  void Stop();

private:
  void WorkerLoop(int thread);
  void Drain(int thread);

  std::vector<std::thread> Workers_;
  std::mutex Mutex_;
  std::condition_variable Wake_;
  std::atomic<bool> Stopping_{false};
  std::atomic<uint64_t> Generation_{0};
  std::atomic<int> Next_{0};
  std::atomic<int> Remaining_{0};
  std::atomic<int> Busy_{0};
  std::atomic<int> Tasks_{0};
  std::atomic<const std::function<void(int, int)>*> Fn_{nullptr};
};

} // namespace bm
