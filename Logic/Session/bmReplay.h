// bmReplay.h - re-running a recorded session: the recorded device poses (and spindle speeds,
// and resume marks) are fed frame by frame, off-thread and back to back, into a fresh proxy on a
// fresh copy of the scene's bone, and the forces compared with the recorded ones. Everything the
// frame computes is a deterministic function of those inputs (fixed-point engine sums, the
// orientation rebuilt from the recorded quaternion), so a faithful replay matches to the last bit;
// the tolerances only absorb nothing-but-rounding differences between builds.
//
// Units: N, N mm, mm.
#pragma once

#include <string>
#include <vector>

#include "bmFrameRecord.h"
#include "bmMachiningSetup.h"
#include "bmSessionRecorder.h"

namespace bm {

/// Every quantity a frame produces, compared: the forces on the proxy and at the device (what the
/// hand felt), thrust, torque, the proxy's position, the feed and the bone removed. The inputs
/// (device pose, speed, buttons, resume marks) are what is replayed; the compute time is this
/// machine's.
struct ReplayResult {
  int64_t frames = 0;
  double maxCouplingForceDiffN = 0; ///< max |coupling force replayed - recorded|, N
  double maxDeviceForceDiffN = 0;   ///< max |device force replayed - recorded|, N
  double maxThrustDiffN = 0;
  double maxTorqueDiffNmm = 0;
  double maxProxyDiffMm = 0;
  double maxFeedDiffMmPerRev = 0;
  double maxRemovedVolumeDiffMm3 = 0; ///< per frame
  int64_t maxRemovedVoxelsDiff = 0;   ///< per frame
  std::vector<FrameRecord> replayed; ///< the replayed records (frameMs = this run's compute time)

  /// The quantities whose largest difference exceeds `tolerance` (N, N mm, mm, mm/rev, mm^3;
  /// removed voxels must match exactly), e.g. {"device force", "proxy position"}; empty when the
  /// replay reproduced the recording.
  std::vector<std::string> Differing(double tolerance) const;
};

/// Throws std::runtime_error naming the frame and the field when the recording cannot be replayed:
/// no frames; a non-finite device pose, spindle speed, recorded force, thrust, torque, proxy
/// position, feed or removed volume; frames not numbered 0, 1, 2, ... (one missing, repeated or
/// renumbered: the replay would not run the session's frames); a time column that is not
/// frame / rate_hz (the recording's session rate).
void CheckReplayable(const Recording& rec);

/// Replays `rec` on `setup` (built from the recording's scene, with an untouched bone). Checks
/// the recording first (CheckReplayable).
ReplayResult Replay(const Recording& rec, MachiningSetup& setup);

/// Builds the scene of a recording (any bone type; a CT scene's relative paths resolve against
/// the recorded "scene_base_dir"). Throws std::runtime_error when the metadata has no scene.
Scene RecordedScene(const Recording& rec);

} // namespace bm
