#include "bmFrameGeometry.h"

#include <algorithm>
#include <climits>

#include <Eigen/Geometry>

#include "bmCpuEngine.h"

namespace bm {

FrameGeometry::FrameGeometry(const FrameInput& in, const PointShell& shell, const Voxmap& bone)
    : rotation(in.rotation), position(in.position), dims(bone.Dims()), pitch(bone.Pitch()),
      brickDims(bone.BrickDims()), index32(bone.StorageSize() <= INT32_MAX) {
  if (shell.Mode() == LipMode::Instantaneous)
    rotation =
        rotation * Eigen::AngleAxisd(in.spindleAngle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double hs = shell.Spacing(), hv = bone.Spacing();
  VoxelMm_ = hv;
  const Eigen::Vector3d so(shell.Origin()[0], shell.Origin()[1], shell.Origin()[2]);
  VoxmapOrigin_ = Eigen::Vector3d(bone.Origin()[0], bone.Origin()[1], bone.Origin()[2]);
  const Eigen::Matrix3d Ad = rotation * (hs / hv);
  const Eigen::Vector3d bd = (rotation * so + in.position - VoxmapOrigin_) / hv;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      A[size_t(3 * r + c)] = float(Ad(r, c));
    b[size_t(r)] = float(bd(r));
  }
  motionTool = rotation.transpose() * in.motion;
  unitsPerMm3 = Voxmap::kFull / bone.VoxelVolume();
  remove = in.removeMaterial && motionTool.squaredNorm() > 0;
  cutting = in.speedRpm > 0 && in.feedMmPerRev > 0;
  maxUnits = MaxRemovalUnits(motionTool, hv, unitsPerMm3);
}

void FrameGeometry::VoxelBox(const std::array<float, 3>& lo, const std::array<float, 3>& hi,
                             std::array<int, 3>& vlo, std::array<int, 3>& vhi) const {
  // Written out in scalars, in the order the OpenCL kernel repeats (bmVpsFrame.cl BlockVisible):
  // world = R p + position (each row summed left to right), grid = (world - origin) / h.
  vlo = {INT_MAX, INT_MAX, INT_MAX};
  vhi = {INT_MIN, INT_MIN, INT_MIN};
  for (int c = 0; c < 8; ++c) {
    const double p0 = (c & 1) ? hi[0] : lo[0], p1 = (c & 2) ? hi[1] : lo[1],
                 p2 = (c & 4) ? hi[2] : lo[2];
    for (int a = 0; a < 3; ++a) {
      const double w = rotation(a, 0) * p0 + rotation(a, 1) * p1 + rotation(a, 2) * p2;
      const double g = (w + position(a) - VoxmapOrigin_(a)) / VoxelMm_;
      const int v = int(std::floor(g + 0.5));
      vlo[size_t(a)] = std::min(vlo[size_t(a)], v);
      vhi[size_t(a)] = std::max(vhi[size_t(a)], v);
    }
  }
}

void FrameGeometry::UnturnLateral(FrameResult& r, const FrameInput& in, const PointShell& shell) {
  if (shell.Mode() != LipMode::Instantaneous)
    return;
  const double c = std::cos(in.spindleAngle), s = std::sin(in.spindleAngle);
  const double fx = r.forceTool(0), fy = r.forceTool(1);
  r.forceTool(0) = c * fx - s * fy;
  r.forceTool(1) = s * fx + c * fy;
}

bool FrameGeometry::ToolMeetsBone(const ToolModel& tool, const Voxmap& bone) const {
  const double R = tool.OuterRadius();
  const auto zr = tool.AxialRange();
  Box3 tb{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d w =
        rotation * Eigen::Vector3d((c & 1) ? R : -R, (c & 2) ? R : -R, (c & 4) ? zr[1] : zr[0]) +
        position;
    for (int a = 0; a < 3; ++a) {
      tb.lo[size_t(a)] = std::min(tb.lo[size_t(a)], w(a));
      tb.hi[size_t(a)] = std::max(tb.hi[size_t(a)], w(a));
    }
  }
  return tb.Intersects(bone.Bounds());
}

} // namespace bm
