// bmWorkerPool.h - persistent worker threads for the per-frame parallel loops.
//
// Threads are started once and joined in Stop() / the destructor: no thread is created per
// frame (that costs ~50 us and sometimes > 1 ms here). Run(n, fn) hands out task indices
// 0..n-1 one at a time from an atomic counter tagged with the run's number, so a task is claimed
// only by a thread that is running when it is handed out. The calling thread claims tasks too
// and, once none is left to claim, waits only for the tasks other threads have claimed and not
// finished. A worker that has not woken up (descheduled, the other core busy with a build) costs
// nothing: the caller does every task itself. Callers should cut the work into many small tasks,
// so that a worker descheduled in the middle of one holds little of it.
//
// Waiting, never by yielding (sched_yield hands the core to any other runnable process for its
// whole time slice, milliseconds under load):
//  - the caller spins (pause) for the claimed tasks: they are running, microseconds each;
//  - an idle worker spins (pause) for the next run for up to spinMicroseconds (default 250: a
//    frame's runs follow each other within microseconds; between 1 kHz frames it may sleep),
//    then sleeps on a futex (std::atomic::wait) until a run or Stop() wakes it, leaving the core
//    to other threads when the haptic loop idles; a run wakes sleeping workers with one notify
//    (a few us for the caller; with RunRedoable the caller does not wait for the wake-up). A
//    worker that spins long on a shared core uses up its share of the core and is descheduled
//    more often.
// RunRedoable() goes one step further for work that may run twice: the caller never waits for a
// worker. Once no task is left to claim, it runs again every task whose claimed run has not
// finished, and the first run of a task to finish counts (Winner()). A worker descheduled in the
// middle of a task then costs the caller one task, never the worker's time slice.
// Run() and RunRedoable() are called from one thread at a time.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace bm {

class WorkerPool {
public:
  /// threads >= 1: total threads including the caller (threads - 1 workers are started).
  /// spinMicroseconds: how long an idle worker polls for the next run before it sleeps, us.
  explicit WorkerPool(int threads, int spinMicroseconds = 250);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int Threads() const { return int(Workers_.size()) + 1; }
  /// Runs fn(task, thread) for task in [0, tasks); thread in [0, Threads()), 0 = the caller.
  /// Every task runs exactly once. Blocks until done.
  void Run(int tasks, const std::function<void(int task, int thread)>& fn);

  /// Task function of RunRedoable(), held by the workers that run it.
  using RedoableFn = std::function<void(int task, int thread)>;
  /// Room for RunRedoable() runs of up to maxTasks tasks; call before the first one.
  void ReserveRedoable(int maxTasks);
  /// Runs (*fn)(task, thread) for task in [0, tasks) (tasks <= the reserved count) and returns
  /// once each task has finished at least once; Winner(task) is the thread whose run finished
  /// first. A task may run on two threads at once, and a worker's run may still be going on
  /// after this returns (even during later runs; Stop() waits for it): fn must write only
  /// outputs private to (task, thread), keep what it reads alive itself (captured by value; the
  /// workers hold fn), and stay in bounds whatever it reads from memory the caller rewrites
  /// later; only the winner's outputs may be used.
  void RunRedoable(int tasks, std::shared_ptr<const RedoableFn> fn);
  /// Thread whose run of `task` counted in the last RunRedoable() (0 = the caller).
  int Winner(int task) const {
    return int(TaskDone_[size_t(task)].load(std::memory_order_acquire) & kThreadMask);
  }
  /// Stops and joins the workers; Run() afterwards runs on the caller alone.
  void Stop();

private:
  void WorkerLoop(int thread);
  /// Claims and runs tasks of run `run` until none is left; returns how many it ran. The caller
  /// passes the redoable run's fn; workers fetch it from Job_.
  /// `tag`: the run's number as in Claim_ (its low kTagBits bits).
  int Drain(uint32_t tag, int thread, const RedoableFn* redoable = nullptr);
  /// Before a new run's task count is stored: sets the claim counter to the run `tag`, closed,
  /// so that no worker late for the previous run can claim past its end.
  void CloseClaims(uint32_t tag);
  /// Marks `task` finished in run `run` by `thread` unless a run of it finished already.
  void Finish(int task, uint64_t run, int thread);

  static constexpr int kTaskBits = 32;
  static constexpr uint64_t kNoTask = 0xFFFFFFFF; ///< in Claim_: a closed run (no task to claim)
  static constexpr uint64_t kRedoableBit = uint64_t(1) << 63; ///< in Claim_: a RunRedoable()
  static constexpr uint32_t kTagMask = 0x7FFFFFFF; ///< run number bits in Claim_ and Wake_
  static constexpr uint64_t kThreadMask = 0xFF;    ///< TaskDone_: (run << 8) | winning thread
  struct Published {
    uint64_t run = 0;
    std::shared_ptr<const RedoableFn> fn;
  };

  std::vector<std::thread> Workers_;
  int SpinMicroseconds_ = 250;
  /// (redoable bit, run number's low 31 bits << kTaskBits) | next task index; a claim is a
  /// compare-and-swap that fails once a newer run has been published.
  alignas(64) std::atomic<uint64_t> Claim_{0};
  /// Run number workers wait on (futex word); bumped after a run is published, and by Stop().
  std::atomic<uint32_t> Wake_{0};
  std::atomic<int> Sleepers_{0};         ///< workers asleep (or about to be) on Wake_
  alignas(64) std::atomic<int> Done_{0}; ///< the current run's tasks finished by workers
  std::atomic<bool> Stopping_{false};
  std::atomic<int> Tasks_{0}; ///< tasks of the current run (stored after CloseClaims)
  std::atomic<const std::function<void(int, int)>*> Fn_{nullptr};
  uint32_t Run_ = 0; ///< the caller's run counter
  /// The current RunRedoable()'s fn, behind a mutex held only to copy or swap the pointer (GCC 12's
  /// std::atomic<std::shared_ptr> unlocks its loads with relaxed order: ThreadSanitizer reports
  /// it).
  std::mutex JobMutex_;
  std::shared_ptr<const Published> Job_;
  std::unique_ptr<std::atomic<uint64_t>[]> TaskDone_; ///< per task: (run << 8) | winner
  int MaxRedoable_ = 0;
};

} // namespace bm
