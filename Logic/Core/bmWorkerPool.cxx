#include "bmWorkerPool.h"

#include <chrono>
#include <stdexcept>

namespace bm {

namespace {

// One spin-wait step: tells the core this is a busy-wait loop (x86 pause), no system call.
inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

} // namespace

WorkerPool::WorkerPool(int threads, int spinMicroseconds) : SpinMicroseconds_(spinMicroseconds) {
  if (threads < 1)
    throw std::invalid_argument("worker pool needs >= 1 thread");
  if (threads > int(kThreadMask))
    throw std::invalid_argument("worker pool: too many threads");
  for (int t = 1; t < threads; ++t)
    Workers_.emplace_back([this, t] { WorkerLoop(t); });
}

WorkerPool::~WorkerPool() {
  Stop();
}

void WorkerPool::Stop() {
  Stopping_.store(true, std::memory_order_seq_cst);
  Wake_.fetch_add(1, std::memory_order_seq_cst);
  Wake_.notify_all();
  for (auto& w : Workers_)
    if (w.joinable())
      w.join();
  Workers_.clear();
}

void WorkerPool::ReserveRedoable(int maxTasks) {
  if (maxTasks <= MaxRedoable_)
    return;
  if (Run_ != 0)
    throw std::logic_error("WorkerPool::ReserveRedoable after the first run");
  TaskDone_ = std::make_unique<std::atomic<uint64_t>[]>(size_t(maxTasks));
  for (int t = 0; t < maxTasks; ++t)
    TaskDone_[size_t(t)].store(0, std::memory_order_relaxed);
  MaxRedoable_ = maxTasks;
}

void WorkerPool::Finish(int task, uint64_t run, int thread) {
  auto& done = TaskDone_[size_t(task)];
  uint64_t d = done.load(std::memory_order_acquire);
  // The first run of the task to finish in run `run` wins; later ones (a worker that was
  // descheduled, the caller's second run) leave it.
  while ((d >> 8) < run)
    if (done.compare_exchange_weak(d, (uint64_t(run) << 8) | uint64_t(thread),
                                   std::memory_order_acq_rel, std::memory_order_acquire))
      return;
}

void WorkerPool::CloseClaims(uint32_t tag) {
  // A worker still draining the previous run holds its exhausted counter (index = its task
  // count). Were the new, larger task count stored first, that worker could read it, find a task
  // left and win its compare-and-swap against the unchanged counter: a claim past the previous
  // run's end, calling its function after it returned. Changing the counter first makes that
  // compare-and-swap fail: a worker that reads the new count (acquire, after the release store
  // that follows) finds the counter changed. The closed counter (new tag, no task left) admits
  // no claim until the run is published.
  Claim_.store((uint64_t(tag) << kTaskBits) | kNoTask, std::memory_order_relaxed);
}

int WorkerPool::Drain(uint32_t tag, int thread, const RedoableFn* redoable) {
  int ran = 0;
  std::shared_ptr<const Published> job;  // a worker's hold on the redoable fn
  uint64_t run = thread == 0 ? Run_ : 0; // a worker takes it from the job
  uint64_t c = Claim_.load(std::memory_order_acquire);
  for (;;) {
    if (uint32_t((c & ~kRedoableBit) >> kTaskBits) != tag)
      break; // a newer run: this one is over
    const int task = int(uint32_t(c));
    // Tasks_ may already be a newer run's (acquire: then this run's claims were closed before
    // it, see CloseClaims, and the compare-and-swap below fails).
    if (task >= Tasks_.load(std::memory_order_acquire))
      break;
    if (!Claim_.compare_exchange_weak(c, c + 1, std::memory_order_acq_rel,
                                      std::memory_order_acquire))
      continue; // c reloaded
    if (c & kRedoableBit) {
      if (!redoable) {
        if (!job) {
          std::lock_guard<std::mutex> lock(JobMutex_);
          job = Job_;
        }
        if (uint32_t(job->run & kTagMask) != tag)
          break; // the caller has finished this run and moved on
        redoable = job->fn.get();
        run = job->run;
      }
      (*redoable)(task, thread);
      Finish(task, run, thread);
    } else {
      // The claim succeeded while run `run` was current, so its fn is alive until Done_ counts
      // this task.
      (*Fn_.load(std::memory_order_relaxed))(task, thread);
      if (thread != 0)
        Done_.fetch_add(1, std::memory_order_release);
    }
    ++ran;
    c = Claim_.load(std::memory_order_acquire);
  }
  return ran;
}

void WorkerPool::Run(int tasks, const std::function<void(int, int)>& fn) {
  if (tasks <= 0)
    return;
  if (Workers_.empty() || tasks == 1) {
    for (int t = 0; t < tasks; ++t)
      fn(t, 0);
    return;
  }
  // No worker holds a claim of the previous run (it ended when all its tasks were done, or it is
  // a redoable run's, which Done_ does not count), and a worker that read its counter late fails
  // its compare-and-swap against the new run number.
  ++Run_;
  const uint32_t tag = uint32_t(Run_) & kTagMask;
  CloseClaims(tag);
  Fn_.store(&fn, std::memory_order_relaxed);
  Tasks_.store(tasks, std::memory_order_release);
  Done_.store(0, std::memory_order_relaxed);
  Claim_.store(uint64_t(tag) << kTaskBits, std::memory_order_release);
  // seq_cst pairs with the worker's Sleepers_ increment then Wake_ check: either it sees the
  // new run or this sees it asleep and wakes it.
  Wake_.store(tag, std::memory_order_seq_cst);
  if (Sleepers_.load(std::memory_order_seq_cst) > 0)
    Wake_.notify_all();
  const int mine = Drain(tag, 0);
  // Every task is claimed: wait for the ones workers are running (spin: they are short).
  while (Done_.load(std::memory_order_acquire) + mine < tasks)
    CpuRelax();
}

void WorkerPool::RunRedoable(int tasks, std::shared_ptr<const RedoableFn> fn) {
  if (tasks <= 0)
    return;
  if (tasks > MaxRedoable_)
    throw std::invalid_argument("WorkerPool::RunRedoable: more tasks than reserved");
  ++Run_;
  if (Workers_.empty()) {
    for (int t = 0; t < tasks; ++t) {
      (*fn)(t, 0);
      Finish(t, Run_, 0);
    }
    return;
  }
  std::shared_ptr<const Published> job = std::make_shared<const Published>(Published{Run_, fn});
  {
    std::lock_guard<std::mutex> lock(JobMutex_);
    Job_.swap(job);
  } // the previous run's job (in `job`) is released outside the lock
  const uint32_t tag = uint32_t(Run_) & kTagMask;
  CloseClaims(tag);
  Tasks_.store(tasks, std::memory_order_release);
  Claim_.store(kRedoableBit | (uint64_t(tag) << kTaskBits), std::memory_order_release);
  Wake_.store(tag, std::memory_order_seq_cst);
  if (Sleepers_.load(std::memory_order_seq_cst) > 0)
    Wake_.notify_all();
  Drain(tag, 0, fn.get());
  // Every task is claimed. Run again those whose claimed run has not finished: a worker may be
  // in the middle of one, or descheduled for milliseconds.
  for (int t = 0; t < tasks; ++t)
    if ((TaskDone_[size_t(t)].load(std::memory_order_acquire) >> 8) != Run_) {
      (*fn)(t, 0);
      Finish(t, Run_, 0);
    }
}

void WorkerPool::WorkerLoop(int thread) {
  using Clock = std::chrono::steady_clock;
  // Wake_'s value at construction: a worker that starts after the first run or Stop() sees the
  // change.
  uint32_t seen = 0;
  for (;;) {
    uint32_t w = Wake_.load(std::memory_order_acquire);
    if (w == seen) {
      // Spin for the next run for a bounded time, then sleep on the futex.
      const auto until = Clock::now() + std::chrono::microseconds(SpinMicroseconds_);
      for (int i = 1; w == seen; ++i) {
        CpuRelax();
        w = Wake_.load(std::memory_order_acquire);
        if ((i & 63) == 0 && Clock::now() >= until)
          break;
      }
      if (w == seen) {
        Sleepers_.fetch_add(1, std::memory_order_seq_cst);
        if (Wake_.load(std::memory_order_seq_cst) == seen)
          Wake_.wait(seen, std::memory_order_seq_cst);
        Sleepers_.fetch_sub(1, std::memory_order_seq_cst);
        continue;
      }
    }
    if (Stopping_.load(std::memory_order_acquire))
      return;
    seen = w;
    Drain(w & kTagMask, thread);
  }
}

} // namespace bm
