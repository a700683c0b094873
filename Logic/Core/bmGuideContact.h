// bmGuideContact.h - whether a tool's non-cutting guide (a reamer's nipple) meets solid bone.
//
// A nipple-guided reamer runs in a guide-pin hole drilled first. The engine removes with the
// whole tool envelope (Docs/Model.md section 5), so a scripted feed would carry the nipple through
// solid bone and leave no trace of it. A scripted run therefore asks this check before each frame:
// the nipple's leading end disc (tool frame z = -nippleLength, radius nippleRadius less one voxel,
// so that the partial-volume wall of a hole barely wider than the nipple does not count) is sampled
// on rings about half a voxel apart; the guide is blocked when any sample lies in a voxel at least
// half full. The run then stops there, as a rigid guide would, and says so. The haptic session
// stops rigid parts by its own contact model (bmProxy.h) and does not use this.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "bmEngine.h"
#include "bmToolModel.h"
#include "bmVoxmap.h"

namespace bm {

class GuideContact {
public:
  /// Samples the guide of `tool` against `bone`. A tool without a guide (drills, burrs, a reamer
  /// with nippleRadius 0) has no samples and is never blocked.
  GuideContact(const ToolModel& tool, const Voxmap& bone);

  bool HasGuide() const { return !Samples_.empty(); }
  /// Fraction (0..1) of the fullest voxel under the guide's end at this pose; 0 with no guide.
  double MaxFill(const FrameInput& pose) const;
  /// true when the guide's end would stand in solid bone (a voxel at least half full).
  bool Blocked(const FrameInput& pose) const { return MaxFill(pose) >= 0.5; }
  /// The guide's end disc radius (mm) and protrusion beyond the face (mm); 0 with no guide.
  double RadiusMm() const { return Radius_; }
  double LengthMm() const { return Length_; }

private:
  const Voxmap& Bone_;
  std::vector<Eigen::Vector3d> Samples_; ///< tool frame, mm
  double Radius_ = 0, Length_ = 0;
};

} // namespace bm
