#include "bmWorkerPool.h"

#include <stdexcept>

namespace bm {

WorkerPool::WorkerPool(int threads) {
  if (threads < 1)
    throw std::invalid_argument("worker pool needs >= 1 thread");
  for (int t = 1; t < threads; ++t)
    Workers_.emplace_back([this, t] { WorkerLoop(t); });
}

WorkerPool::~WorkerPool() {
  Stop();
}

void WorkerPool::Stop() {
  {
    std::lock_guard<std::mutex> lock(Mutex_);
    Stopping_.store(true);
  }
  Wake_.notify_all();
  for (auto& w : Workers_)
    if (w.joinable())
      w.join();
  Workers_.clear();
}

void WorkerPool::Drain(int thread) {
  for (;;) {
    const int task = Next_.fetch_add(1, std::memory_order_acq_rel);
    if (task >= Tasks_.load(std::memory_order_acquire))
      break;
    (*Fn_.load(std::memory_order_acquire))(task, thread);
    Remaining_.fetch_sub(1, std::memory_order_acq_rel);
  }
}

void WorkerPool::Run(int tasks, const std::function<void(int, int)>& fn) {
  if (tasks <= 0)
    return;
  if (Workers_.empty() || tasks == 1) {
    for (int t = 0; t < tasks; ++t)
      fn(t, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(Mutex_);
    // A worker waking late from the previous run may still fetch_add: park the counter out of
    // range while the new run is set up, then open it.
    Next_.store(1 << 30, std::memory_order_release);
    Fn_.store(&fn, std::memory_order_release);
    Tasks_.store(tasks, std::memory_order_release);
    Remaining_.store(tasks, std::memory_order_release);
    Next_.store(0, std::memory_order_release);
    Generation_.fetch_add(1, std::memory_order_acq_rel);
  }
  Wake_.notify_all();
  Drain(0);
  while (Remaining_.load(std::memory_order_acquire) > 0)
    std::this_thread::yield();
  // Workers may still be between their last fetch_add and going idle: wait until none holds Fn_.
  while (Busy_.load(std::memory_order_acquire) > 0)
    std::this_thread::yield();
}

void WorkerPool::WorkerLoop(int thread) {
  uint64_t seen = 0;
  for (;;) {
    // Spin briefly for the next frame's run, then sleep.
    bool woke = false;
    for (int spin = 0; spin < 2000 && !woke; ++spin) {
      if (Stopping_.load(std::memory_order_acquire))
        return;
      woke = Generation_.load(std::memory_order_acquire) != seen;
      if (!woke)
        std::this_thread::yield();
    }
    if (!woke) {
      std::unique_lock<std::mutex> lock(Mutex_);
      Wake_.wait(lock, [&] { return Stopping_.load() || Generation_.load() != seen; });
      if (Stopping_.load())
        return;
    }
    {
      std::lock_guard<std::mutex> lock(Mutex_);
      if (Stopping_.load())
        return;
      seen = Generation_.load();
      Busy_.fetch_add(1, std::memory_order_acq_rel);
    }
    Drain(thread);
    Busy_.fetch_sub(1, std::memory_order_acq_rel);
  }
}

} // namespace bm
