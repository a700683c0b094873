// bmEngine.h - one haptic frame of the voxmap-point-shell machining loop, backend-independent.
//
// A frame (Faieghi et al. section II): bounding-box pre-check, per-element collision against the
// voxmap, elemental cutting forces of the engaged cutting elements, removal of the material the
// tool envelope sweeps, and accumulation of thrust and torque in fixed-point integers so that the
// totals do not depend on thread count or order. Engagement is decided on the voxmap as it was at
// the start of the frame; removal is applied after (so results are deterministic).
//
// Frames: tool frame T (bmToolModel.h); pose maps T to world. Thrust > 0 pushes the tool back out
// of the bone along +z_t; resisting torque > 0 opposes the spindle, which turns about +z_t.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <Eigen/Core>

namespace bm {

/// Fixed-point scale of the accumulators: 2^32 units per N (or N mm).
constexpr double kForceFixedScale = 4294967296.0;

struct FrameInput {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity(); ///< tool -> world
  Eigen::Vector3d position = Eigen::Vector3d::Zero();     ///< world mm of the tool frame origin
  Eigen::Vector3d motion = Eigen::Vector3d::Zero(); ///< tool displacement over this frame, world mm
  double feedMmPerRev = 0.02; ///< feed per revolution f, mm/rev (sets the chip area)
  double speedRpm = 1000;     ///< spindle speed n, rpm (0: spindle stopped, no cutting force)
  double spindleAngle = 0;    ///< rad; turns the shell with instantaneous lips
  bool removeMaterial = true; ///< false: query forces only, leave the voxmap unchanged
  /// true (default): every engaged element removes what its surface sweeps, the whole tool
  /// envelope (Docs/Model.md section 5: margins and shank never drag on what the lips left);
  /// false: only cutting elements remove (a study option; the haptic session keeps the envelope
  /// and stops its rigid parts by contact, because lips-only removal leaves grid-aliasing
  /// remnants that stall a reamer on coarse voxmaps).
  bool envelopeRemoves = true;
};

struct FrameResult {
  double thrustN = 0;                                  ///< F = sum dF_z, N
  double torqueNmm = 0;                                ///< M = -sum r dF_y, N mm
  Eigen::Vector3d forceTool = Eigen::Vector3d::Zero(); ///< (lateral x, lateral y, thrust) in T, N
  int64_t thrustFixed = 0, torqueFixed = 0;            ///< the exact fixed-point sums
  int64_t visitedElements = 0; ///< elements tested against the voxmap (after culling)
  int64_t engagedElements = 0; ///< elements inside bone
  int64_t engagedCutting = 0;  ///< cutting elements inside bone
  int64_t removedVoxels = 0;   ///< voxels this frame took to void
  int64_t removedFill = 0;     ///< fill units removed (Voxmap::kFull per voxel)
  double removedVolumeMm3 = 0; ///< removedFill as mm^3
  double sweptVolumeMm3 = 0;   ///< volume the engaged elements asked to remove, mm^3
};

class Engine {
public:
  virtual ~Engine() = default;
  /// "cpu" or "opencl" plus the method, e.g. "cpu/lazar".
  virtual std::string Name() const = 0;
  /// Advance one frame. Throws on a backend fault; the voxmap is then as before the frame.
  virtual FrameResult Step(const FrameInput& in) = 0;
  /// Bring the Voxmap given at construction up to date when the backend keeps its own copy
  /// (device memory, octree). Backends that cut the Voxmap in place need nothing.
  virtual void SyncBone() {}
};

} // namespace bm
