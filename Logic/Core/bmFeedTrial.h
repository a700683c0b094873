// bmFeedTrial.h - a robot-driven trial: the tool fed along its axis at prescribed feed and speed
// (the way the papers validate), one engine frame per haptic period, with the per-frame record
// and the summary `bmsim run` writes (forces.csv, summary.json).
//
// "Fully engaged" = the foremost cutting point deeper than the edges' full-engagement depth plus
// two voxels and one shell spacing; means and ripple (std / mean) are taken there. The reference
// is the same force model integrated along the edges (bmForceModel.h IntegrateEdges).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bmMachiningSetup.h"

namespace bm {

struct TrialFrame {
  double timeS = 0;   ///< s since the start
  double depthMm = 0; ///< foremost cutting point below the entry point, mm (< 0 above)
  double feedMmPerRev = 0;
  double thrustN = 0;
  double torqueNmm = 0;
  double frameMs = 0;        ///< engine time of this frame, ms
  int64_t removedVoxels = 0; ///< voxels taken to void this frame
  double removedVolumeMm3 = 0;
  double lateralN = 0; ///< |lateral force| in the tool frame, N
};

class FeedTrial {
public:
  explicit FeedTrial(MachiningSetup& setup);
  /// Runs every frame to the final depth. progress(fraction) may return false to cancel
  /// (then Run returns false and the record holds the frames so far). A tool whose non-cutting
  /// guide (a reamer's nipple) would enter solid bone stops before that frame, as a rigid guide
  /// would (bmGuideContact.h): Run returns true, GuideStopDepthMm() says where, and Warnings()
  /// says why.
  bool Run(const std::function<bool(double)>& progress = {});
  /// Whether the guide met solid bone and the feed stopped early.
  bool GuideBlocked() const { return GuideBlocked_; }
  /// Depth of the foremost cutting point (mm below the entry; negative above it) where the feed
  /// stopped when GuideBlocked().
  double GuideStopDepthMm() const { return GuideStop_; }
  /// What the run found worth telling (the tool starts inside bone, the entry lies outside all
  /// bone, the guide stopped, nothing removed); empty when nothing.
  const std::vector<std::string>& Warnings() const { return Warnings_; }

  const std::vector<TrialFrame>& Frames() const { return Frames_; }
  double FinalDepthMm() const { return FinalDepth_; }
  double EngagedDepthMm() const { return EngagedDepth_; }
  /// Summary as documented in README (thrust_N, torque_Nmm, thrust_ripple, reference_*,
  /// frame_ms_p50/p99, removed_volume_mm3, resolutions, method, threads, ...).
  nlohmann::json Summary() const;
  /// Writes DIR/forces.csv and DIR/summary.json together (both or neither appear); creates DIR if
  /// missing.
  void WriteOutputs(const std::string& dir) const;

private:
  /// Warns when the tool starts inside bone or the entry lies outside all bone (along the axis).
  void CheckPath();

  MachiningSetup& Setup_;
  std::vector<TrialFrame> Frames_;
  double FinalDepth_ = 0, EngagedDepth_ = 0;
  double SweptVolume_ = 0, RemovedVolume_ = 0;
  int64_t RemovedVoxels_ = 0;
  bool GuideBlocked_ = false;
  double GuideStop_ = 0;
  std::vector<std::string> Warnings_;
};

/// The straight feed path of a scene's trial (shared by the trial and the benchmark).
class FeedPath {
public:
  explicit FeedPath(const MachiningSetup& setup);
  /// Feed per frame period along the axis, mm.
  double StepMm() const { return Step_; }
  /// Frame k (0-based) with the foremost cutting point depthMm below the entry point: the tool
  /// on the trial axis, moved one step along -axis this frame, the spindle turned k + 1 periods.
  FrameInput Frame(double depthMm, int64_t k) const;

private:
  TrialSpec T_;
  Eigen::Matrix3d Rot_;
  Eigen::Vector3d Axis_;
  double Zf_ = 0, Step_ = 0;
};

/// Percentile (0..100) of a sample, by nearest rank; 0 for an empty sample.
double Percentile(std::vector<double> v, double pct);

} // namespace bm
