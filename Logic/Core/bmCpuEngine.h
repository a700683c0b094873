// bmCpuEngine.h - the frame of bmEngine.h on the CPU with persistent worker threads.
//
// Culling rules (Docs/CostModel.md section 3), each exact (tests show identical totals and
// removal with and without them):
//  1. a block of elements whose bounding box, carried into the voxmap, covers no brick holding
//     bone is skipped: none of its elements can be inside bone;
//  2. a block without cutting elements whose normals cannot face the frame's motion
//     (max over the block's normal bounds of n . d <= 0) is skipped: its elements sweep no
//     material and produce no cutting force (margins sliding along a wall the envelope already
//     cut).
//
// Work split (the frame's pass over the blocks): tasks of kBlocksPerTask blocks, claimed one at a
// time and run with WorkerPool::RunRedoable, so the caller never waits for a worker: a task a
// worker has not finished when the caller runs out of tasks (the worker descheduled by a build on
// the other core, for milliseconds) is run again by the caller, and the first run to finish
// counts. So a task's run writes only its own outputs: partial sums and removal requests per
// (task, thread), fixed-point, so the totals do not depend on which thread ran which task; and
// the element residency, double-buffered per thread: a run reads the buffer of the thread that
// won the task in the previous frame and writes its own thread's buffer of this frame's parity
// (results identical to one thread updating it in place). A losing run may go on after the frame:
// it holds the frame's context (PassJob) and reads fills, residency and force table as relaxed
// atomics, since the caller may be rewriting them.
// Removal (after the pass: engagement is decided on the voxmap as the frame found it): the pass
// files each request under its voxel's owner, one of P parts (P = threads rounded up to a power
// of two; Voxmap::LineOwner: the voxel's cache line modulo P), and a task of WorkerPool::Run per
// part applies its requests with Voxmap::RemoveOwned: plain stores, no locked decrement, since
// no other part writes those fills (removal is not idempotent, so the caller waits for a part a
// worker has claimed). The fills are prefetched for writing a few requests ahead.
// Elements that stay engaged in the voxel they were in (bmElementResidency.h) need not read its
// fill: the pass prefetches and loads only the others' (at shell 1024^3 the prefetches' misses
// were a third of the pass). The residency is one word per element (PackedResidency) and the
// frame of the last visit one word per block.
// Elemental forces depend on the element's radius only: a table per force bin (averaged over the
// bin's width, bmForceModel.h ForceTable) is evaluated once per (feed, speed) and each engaged
// element adds delta x material x table[bin].
// The pass works in batches of kBatch elements: first their voxels (Morton decode and the float
// transform, loops the compiler vectorises) and the prefetches, then one loop for engagement,
// removal requests and forces, with the sums in registers. Same arithmetic, order and precision
// as the kernels (bmVpsFrame.cl).
// An engine on one thread runs the incremental pass (bmIncrementalPass.h: only the elements whose
// voxel can have changed are recomputed, the engaged ones summed from a list; same results) when
// the previous frame ran and the tool's rotation is unchanged, this full pass otherwise.
#pragma once

#include <memory>
#include <vector>

#include "bmElementResidency.h"
#include "bmEngine.h"
#include "bmFrameGeometry.h"
#include "bmForceModel.h"
#include "bmPointShell.h"
#include "bmVoxmap.h"
#include "bmWorkerPool.h"

namespace bm {

struct CullingOptions {
  bool blocks = true; ///< rule 1
  bool motion = true; ///< rule 2
  /// The incremental pass (bmIncrementalPass.h) where it applies (one engine thread, the tool's
  /// rotation unchanged since the previous frame); false: the full pass every frame. Same results.
  bool incremental = true;
};

/// Whether the pass visits block `blk` this frame (the culling rules above, those enabled).
bool BlockVisible(const ShellBlock& blk, const FrameGeometry& G, const Voxmap& bone,
                  const CullingOptions& culling);

class IncrementalPass;

/// A pass task's removal requests for one removal part: an array that a batch first makes room
/// in (Reserve) and then appends to through a pointer, with no check per request. A sentinel
/// request (voxel kNoVoxel) sits before the first, so End()[-1] always exists: "the same voxel as
/// the last request" needs no test for an empty list.
class RequestList {
public:
  static constexpr int64_t kNoVoxel = -2; ///< the sentinel's voxel: no request's
  RequestList() { Reserve(0); }
  const Voxmap::RemovalRequest* Data() const { return Storage_.get() + 1; }
  size_t Size() const { return Size_; }
  void Clear() { Size_ = 0; }
  /// Room for n more requests after Size() (the contents kept).
  void Reserve(size_t n);
  Voxmap::RemovalRequest* End() { return Storage_.get() + 1 + Size_; }
  /// The requests end at `end`, reached from End() within reserved room.
  void SetEnd(const Voxmap::RemovalRequest* end) { Size_ = size_t(end - Data()); }

private:
  std::unique_ptr<Voxmap::RemovalRequest[]> Storage_; ///< the sentinel, then the requests
  size_t Size_ = 0, Capacity_ = 0;
};

/// Partial sums of a part of a frame; fixed-point so that any split sums to the same totals.
struct alignas(64) FramePartial {
  int64_t thrust = 0, torque = 0, fx = 0, fy = 0;
  int64_t visited = 0, engaged = 0, engagedCutting = 0, requested = 0;
  int64_t removedFill = 0, removedVoxels = 0;
  /// Removal requests (voxel index, fill units), one list per removal part: the voxel's owner
  /// (Voxmap::LineOwner).
  std::vector<RequestList> removals;
  void Clear();
  /// Adds o's counts and sums (not its removals).
  void Add(const FramePartial& o);
  /// Stores a pass's sums and counts (kept in registers while it runs).
  void SetSums(int64_t thrustSum, int64_t torqueSum, int64_t fxSum, int64_t fySum,
               int64_t visitedCount, int64_t engagedCount, int64_t engagedCuttingCount,
               int64_t requestedUnits);
};

class CpuEngine final : public Engine {
public:
  /// Most threads an engine runs on (bmsim's --threads allows as many).
  static constexpr int kMaxThreads = 64;
  /// The engine works on `bone` in place; tool, shell and model must outlive it.
  /// threads in 1..kMaxThreads (default 2, this machine's cores); more throws
  /// std::invalid_argument.
  CpuEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell, const ForceModel& model,
            int threads = 2, CullingOptions culling = {});
  ~CpuEngine() override;
  std::string Name() const override { return "cpu/" + ToString(Model_.GetMethod()); }
  FrameResult Step(const FrameInput& in) override;
  int Threads() const { return Pool_.Threads(); }
  /// Frames the incremental pass ran (the others ran the full pass).
  int64_t IncrementalFrames() const;
  /// Elements whose voxel the incremental pass recomputed in blocks visible in consecutive frames
  /// (its windows), over all its frames; blocks newly visible are visited in full besides.
  int64_t IncrementalRecomputed() const;
  /// Makes the next frame run the full pass. Call it after raising fills or changing materials
  /// of the bone in place (loading bone into the same voxmap): the incremental pass relies on
  /// fills only decreasing between frames and reads an element's material when it enters a voxel.
  void ForgetIncremental();
  /// Turns the incremental pass on (where it applies) or off (the full pass every frame), from
  /// the next frame; the results are the same (benchmarks compare the two). Turning it on again
  /// starts with a full pass and its counters (IncrementalFrames, IncrementalRecomputed) at 0.
  void SetIncremental(bool on);

private:
  /// What one frame's pass tasks read, shared with the workers that run them (kept alive by
  /// them: a descheduled worker may finish its copy of a task after the frame).
  struct PassJob {
    FrameGeometry G;
    uint32_t frame = 0;
    bool envelopeRemoves = true;
    std::vector<uint8_t> prevWinner; ///< per task: the thread whose state buffer holds frame - 1
  };
  static size_t NumTasks(const PointShell& shell);
  /// threads, or std::invalid_argument when more than kMaxThreads.
  static int ValidThreads(int threads);
  void UpdateForceTable(double f, double n);
  /// Pass task `task` (its kBlocksPerTask blocks) on `thread`: culling, engagement, removal
  /// requests and forces into Partials_[task * Threads() + thread], residency into that thread's
  /// buffer of this frame's parity.
  void RunPassTask(const PassJob& job, int task, int thread);

  Voxmap& Bone_;
  const ToolModel& Tool_;
  const PointShell& Shell_;
  ForceModel Model_;
  CullingOptions Culling_;
  WorkerPool Pool_;
  static constexpr int kBlocksPerTask = 4; // shell blocks per pass task
  int RemovalParts_ = 1;                   // power of two >= threads
  bool SmallCodes_ = false; // every element code decodes in 32-bit lanes (ElementCoordsOfSmall)
  std::vector<FramePartial> Partials_;           // per (pass task, thread)
  std::unique_ptr<IncrementalPass> Incremental_; // one-thread engines with culling.incremental
  /// Element residency (PackedResidency words) and, per block, the frame of its last visit.
  struct ResidencyBuffer {
    std::vector<uint64_t> words;      ///< per element
    std::vector<uint32_t> blockFrame; ///< per shell block
  };
  /// One buffer per (thread, frame parity): a task's run reads the buffer of the thread that won
  /// the task in the previous frame and writes its own thread's. With one thread, one buffer
  /// updated in place (half the memory traffic).
  std::vector<ResidencyBuffer> State_;
  std::vector<uint8_t> PrevWinner_;                  // per pass task, the last frame's winner
  std::vector<Voxmap::RemovalTotals> RemovalCounts_; // per removal part
  std::vector<std::vector<int64_t>> Touched_;        // per removal part: bricks it changed
  uint32_t Frame_ = 0;
  static constexpr int kBatch = 64; // elements whose voxels are fetched ahead
  /// Per force bin, per mm of delta, times kForceFixedScale (a power of two: the products round
  /// exactly as (w x table) x scale, so the sums are the kernels' to the last unit).
  std::vector<BinForce> Table_;
  double TableFeed_ = -1, TableSpeed_ = -1;
};

/// Most fill units one element may remove from its voxel for motion d (tool frame, mm): the
/// voxel's own swept cross-section, capped at a whole voxel (shared by the CPU engines).
double MaxRemovalUnits(const Eigen::Vector3d& d, double voxelMm, double unitsPerMm3);

/// The shell's force bins as (kind, {centre, width}) for ForceTable().
std::vector<std::pair<EdgeKind, std::array<double, 2>>> ShellBinSpans(const PointShell& shell);

/// A frame's summed partial as its result (forces in N and N mm, volumes in mm^3).
FrameResult FrameResultOf(const FramePartial& total, double voxelVolumeMm3);

} // namespace bm
