// bmTestFeed.h - test helper: feed a tool along its axis into a voxmap frame by frame, driving an
// Engine directly (as bmFeedTrial does, but with any engine, axis and step, keeping every
// FrameResult for exact comparisons).
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "bmEdgeQuadrature.h"
#include "bmEngine.h"
#include "bmToolModel.h"

namespace bm::test {

struct Feed {
  Eigen::Vector3d axis{0, 0, 1};  ///< world direction of z_t (out of the bone)
  Eigen::Vector3d entry{0, 0, 0}; ///< where the axis meets the bone's top face
  /// World direction of the motion (unit); zero = along -axis (feeding). Depth counts along it.
  Eigen::Vector3d direction{0, 0, 0};
  double startDepthMm = -0.02; ///< depth of the foremost cutting point before frame 1
  double stepMm = 0.005;       ///< advance per frame
  int frames = 100;
  double feedMmPerRev = 0.02;
  double speedRpm = 1000;
};

inline Eigen::Matrix3d FeedRotation(const Feed& f) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), f.axis.normalized())
      .toRotationMatrix();
}

inline std::vector<FrameResult> RunFeed(Engine& engine, const ToolModel& tool, const Feed& f) {
  const Eigen::Matrix3d rot = FeedRotation(f);
  const Eigen::Vector3d axis = f.axis.normalized();
  const Eigen::Vector3d dir =
      f.direction.squaredNorm() > 0 ? f.direction.normalized() : Eigen::Vector3d(-axis);
  const double zf = ForemostCuttingZ(tool);
  std::vector<FrameResult> out;
  for (int k = 0; k < f.frames; ++k) {
    const double depth = f.startDepthMm + f.stepMm * (k + 1);
    FrameInput in;
    in.rotation = rot;
    in.position = f.entry + dir * depth - rot * Eigen::Vector3d(0, 0, zf);
    in.motion = dir * f.stepMm;
    in.feedMmPerRev = f.feedMmPerRev;
    in.speedRpm = f.speedRpm;
    in.spindleAngle = 0.3 * (k + 1);
    out.push_back(engine.Step(in));
  }
  engine.SyncBone();
  return out;
}

} // namespace bm::test
