// bmCpuEngine.h - the frame of bmEngine.h on the CPU with persistent worker threads.
//
// Culling rules (MODEL_NOTES section 9), each exact (tests show identical totals and removal with
// and without them):
//  1. a block of elements whose bounding box, carried into the voxmap, covers no brick holding
//     bone is skipped: none of its elements can be inside bone;
//  2. a block without cutting elements whose normals cannot face the frame's motion
//     (max over the block's normal bounds of n . d <= 0) is skipped: its elements sweep no
//     material and produce no cutting force (margins sliding along a wall the envelope already
//     cut).
// Elemental forces depend on the element's radius only: a table per force bin (averaged over the
// bin's width, bmForceModel.h ForceTable) is evaluated once per (feed, speed) and each engaged
// element adds delta x material x table[bin].
#pragma once

#include <memory>
#include <vector>

#include "bmElementResidency.h"
#include "bmEngine.h"
#include "bmForceModel.h"
#include "bmPointShell.h"
#include "bmVoxmap.h"
#include "bmWorkerPool.h"

namespace bm {

struct CullingOptions {
  bool blocks = true; ///< rule 1
  bool motion = true; ///< rule 2
};

/// Per-thread partial sums of a frame; fixed-point so that any split sums to the same totals.
struct alignas(64) FramePartial {
  int64_t thrust = 0, torque = 0, fx = 0, fy = 0;
  int64_t visited = 0, engaged = 0, engagedCutting = 0, requested = 0;
  int64_t removedFill = 0, removedVoxels = 0;
  std::vector<std::pair<int64_t, int32_t>> removals; ///< (voxel index, fill units)
  void Clear();
};

class CpuEngine final : public Engine {
public:
  /// The engine works on `bone` in place; tool, shell and model must outlive it.
  /// threads >= 1 (default 2, this machine's cores).
  CpuEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell, const ForceModel& model,
            int threads = 2, CullingOptions culling = {});
  std::string Name() const override { return "cpu/" + ToString(Model_.GetMethod()); }
  FrameResult Step(const FrameInput& in) override;
  int Threads() const { return Pool_.Threads(); }

private:
  void UpdateForceTable(double f, double n);

  Voxmap& Bone_;
  const ToolModel& Tool_;
  const PointShell& Shell_;
  ForceModel Model_;
  CullingOptions Culling_;
  WorkerPool Pool_;
  std::vector<FramePartial> Partials_;
  std::vector<ElementResidency> State_; // per element
  uint32_t Frame_ = 0;
  static constexpr uint32_t kBatch = 64;           // elements whose voxels are fetched ahead
  std::vector<std::vector<int64_t>> VoxelScratch_; // per thread: the batch's voxel indices
  std::vector<BinForce> Table_;                    // per force bin, per mm of delta
  double TableFeed_ = -1, TableSpeed_ = -1;
};

/// Most fill units one element may remove from its voxel for motion d (tool frame, mm): the
/// voxel's own swept cross-section, capped at a whole voxel (shared by the CPU engines).
double MaxRemovalUnits(const Eigen::Vector3d& d, double voxelMm, double unitsPerMm3);

/// The shell's force bins as (kind, {centre, width}) for ForceTable().
std::vector<std::pair<EdgeKind, std::array<double, 2>>> ShellBinSpans(const PointShell& shell);

/// Sums per-thread partials into a frame result (shared by the CPU engines).
FrameResult SumPartials(const std::vector<FramePartial>& parts, double voxelVolumeMm3);

} // namespace bm
