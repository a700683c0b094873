// bmFrameGeometry.h - what every backend derives from a frame's input before touching elements:
// the affine map from the tool's grid to the voxmap's grid, the motion in the tool frame, and the
// removal scale. One place, so the CPU engines and the OpenCL host code pick the same voxels.
//
// Voxel of an element at tool-grid coordinates (i, j, k): g = A (i, j, k) + b in float, with no
// FMA contraction (the build sets -ffp-contract=off; kernels use FP_CONTRACT OFF), and
// voxel = floor(g + 0.5f) per axis.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "bmEngine.h"
#include "bmPointShell.h"
#include "bmToolModel.h"
#include "bmVoxmap.h"

namespace bm {

struct FrameGeometry {
  /// Derive from the frame input, the shell (its grid; instantaneous shells turn with the
  /// spindle) and the voxmap (its grid).
  FrameGeometry(const FrameInput& in, const PointShell& shell, const Voxmap& bone);

  Eigen::Matrix3d rotation; ///< tool (turned by the spindle angle for instantaneous lips) -> world
  Eigen::Vector3d position; ///< world mm of the tool frame's origin
  std::array<float, 9> A{}; ///< tool grid -> voxmap grid, row-major
  std::array<float, 3> b{};
  Eigen::Vector3d motionTool;     ///< this frame's motion in the (turned) tool frame, mm
  double unitsPerMm3 = 0;         ///< fill units per mm^3 removed
  double maxUnits = 0;            ///< most units one element may take from its voxel this frame
  bool remove = false;            ///< material is removed this frame (asked for and moving)
  bool cutting = false;           ///< spindle turning and feed > 0: cutting forces this frame
  std::array<int, 3> dims{};      ///< voxmap dimensions
  std::array<int, 2> pitch{};     ///< voxmap row and slice pitch (Voxmap::Pitch)
  std::array<int, 3> brickDims{}; ///< voxmap occupancy bricks along each axis
  bool index32 = false;           ///< every voxel index (padding included) fits in an int32

  /// Voxel index holding the element at tool-grid coordinates ijk, or -1 outside the voxmap
  /// (VoxelsOf() for one element: one copy of the arithmetic that the kernels mirror).
  int64_t VoxelOf(const std::array<uint32_t, 3>& ijk) const {
    const float x = float(ijk[0]), y = float(ijk[1]), z = float(ijk[2]);
    int64_t idx = -1;
    int32_t brick = 0;
    VoxelsOf(&x, &y, &z, 1, &idx, &brick);
    return idx;
  }
  /// VoxelOf() for n elements at tool-grid coordinates (x[q], y[q], z[q]) (exact integers as
  /// floats), with each voxel's occupancy brick (Voxmap::BrickOfVoxel, cheaper here from the
  /// coordinates than later from the index): the same arithmetic in a loop the compiler vectorises
  /// (with -fno-trapping-math for floor(); bmCpuEngine.cxx has it). idx[q] = -1 (brick[q] = 0) for
  /// an element outside the voxmap.
  void VoxelsOf(const float* __restrict x, const float* __restrict y, const float* __restrict z,
                int n, int64_t* __restrict idx, int32_t* __restrict brick) const {
    const float a0 = A[0], a1 = A[1], a2 = A[2], a3 = A[3], a4 = A[4], a5 = A[5], a6 = A[6],
                a7 = A[7], a8 = A[8], b0 = b[0], b1 = b[1], b2 = b[2];
    const int nx = dims[0], ny = dims[1], nz = dims[2], bx = brickDims[0], by = brickDims[1];
    const int px = pitch[0], py = pitch[1];
    static_assert(Voxmap::kBrick == 8, "the brick below is the voxel's coordinates >> 3");
    // The index in 32-bit arithmetic where every index fits (the same values: 4 lanes per
    // vector and no emulated 64-bit multiply), in 64-bit arithmetic otherwise.
    auto loop = [&](auto index) {
      for (int q = 0; q < n; ++q) { // an int index: GCC 12 does not vectorise an unsigned one
        const float gx = a0 * x[q] + a1 * y[q] + a2 * z[q] + b0;
        const float gy = a3 * x[q] + a4 * y[q] + a5 * z[q] + b1;
        const float gz = a6 * x[q] + a7 * y[q] + a8 * z[q] + b2;
        const int vi = int(std::floor(gx + 0.5f)), vj = int(std::floor(gy + 0.5f)),
                  vk = int(std::floor(gz + 0.5f));
        const bool in = (unsigned(vi) < unsigned(nx)) & (unsigned(vj) < unsigned(ny)) &
                        (unsigned(vk) < unsigned(nz));
        idx[q] = in ? int64_t(index(vi, vj, vk)) : -1;
        brick[q] = in ? (vi >> 3) + bx * ((vj >> 3) + by * (vk >> 3)) : 0;
      }
    };
    if (index32)
      loop([&](int vi, int vj, int vk) { return vi + px * (vj + py * vk); });
    else
      loop([&](int vi, int vj, int vk) { return vi + int64_t(px) * (vj + int64_t(py) * vk); });
  }
  /// Fill units an element with area-normal `an` (mm^2) asks to remove this frame (0 if none).
  int32_t RemovalUnits(const std::array<float, 3>& an) const {
    const double vol = an[0] * motionTool(0) + an[1] * motionTool(1) + an[2] * motionTool(2);
    if (!(vol > 0))
      return 0;
    return int32_t(std::min(vol * unitsPerMm3, maxUnits) + 0.5);
  }
  /// Voxel-index box (inclusive, unclamped) covered by a tool-frame box in mm.
  void VoxelBox(const std::array<float, 3>& lo, const std::array<float, 3>& hi,
                std::array<int, 3>& vlo, std::array<int, 3>& vhi) const;
  /// Lateral forces summed in the spindle-turned frame of an instantaneous shell, turned back into
  /// the tool frame (nothing to do for time-averaged shells).
  static void UnturnLateral(FrameResult& r, const FrameInput& in, const PointShell& shell);
  /// Whether the tool's bounding box, placed in the world, meets the voxmap's bounds.
  bool ToolMeetsBone(const ToolModel& tool, const Voxmap& bone) const;

private:
  Eigen::Vector3d VoxmapOrigin_;
  double VoxelMm_ = 1;
};

} // namespace bm
