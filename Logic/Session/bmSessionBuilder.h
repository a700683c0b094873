// bmSessionBuilder.h - a scene and a device request turned into a ready haptic session: the bone
// (bmSceneBone.h), the machining setup, the device placed at the trial's start, the session
// options and the session's length. The one way to build a session: bmsim run (session), bmsim
// bench --session and the BM Session source all go through BuildSession (Docs/Session.md,
// "Building a session").
//
// Devices:
//  - Scripted: a simulated hand on a Touch (the Touch's limits, the tool's force scale,
//    SessionForceScale): feed (prescribed feed and speed), force (a constant push), hand
//    (a rising push with tremor) or trajectory (a recorded path) - bmScriptedDevice.h.
//  - Robot: a robot arm feeding the tool along the trial at its feed and speed, a position source
//    (PositionSourceLimits(), force scale 1).
//  - Touch: a 3D Systems Touch through OpenHaptics (bmTouchDevice.h), its workspace centre 10 mm
//    above the entry point along the axis, the tool's force scale (SessionForceScale).
//  - Mouse: a programmable position source whose pose follows a depth (ToolPoseAtDepth), the
//    panel's mouse proxy (PositionSourceLimits(), force scale 1).
// Scripted and robot devices start with the tool's foremost cutting point the trial's clearance
// above the entry point, as the offline feed trial does (bmFeedTrial.h).
//
// Units: mm, N, s, rpm, mm/rev, Hz.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bmDevice.h"
#include "bmHapticSession.h"
#include "bmMachiningSetup.h"
#include "bmProgrammableDevice.h"
#include "bmSceneBone.h"
#include "bmSessionGrid.h"
#include "bmScriptedDevice.h"

namespace bm {

enum class SessionDevice { Scripted, Robot, Touch, Mouse };
const char* ToString(SessionDevice d);
/// "scripted", "robot", "touch" or "mouse"; throws std::invalid_argument listing them.
SessionDevice SessionDeviceFromString(const std::string& s);

/// A firm push of a hand on the Touch, N (of its 3.3 N, leaving room for the lateral forces and
/// the ripple): what the session's force scale is set for, and the scripted hand's default push.
inline constexpr double kFirmPushN = 2.5;

/// What session to build on a scene. Defaults: a scripted feed at the scene's feed and speed.
struct SessionRequest {
  SessionDevice device = SessionDevice::Scripted;
  /// Scripted device's mode (default Feed); a robot always feeds.
  ScriptMode mode = ScriptMode::Feed;
  /// Scripted force and hand modes: the push along the feed at the device, N, in [0, the Touch's
  /// maximum force] (default kFirmPushN, 2.5).
  double appliedForceN = kFirmPushN;
  /// Scripted hand mode: the lateral tremor's amplitude, N, in [0, the Touch's maximum force]
  /// (default 0.1), and its seed (default 1).
  double handTremorN = 0.1;
  uint64_t handSeed = 1;
  /// Scripted force and hand modes: a trained hand that stops pushing at breakthrough
  /// (ScriptedDeviceOptions::stopAtBreakthrough; default false: it pushes on).
  bool stopAtBreakthrough = false;
  /// Scripted trajectory mode: the samples (bmScriptedDevice.h LoadTrajectoryCsv); required there.
  std::vector<TrajectorySample> trajectory;
  /// Tool force = forceScale x device force, in [1e-3, kMaxForceScale]; 0 (default): the
  /// device's (scripted, touch: the tool's, SessionForceScale; robot, mouse: 1).
  double forceScale = 0;
  ContactMethod contact = ProxyOptions().method;  ///< default: the cutting contact
  Rendering rendering = ProxyOptions().rendering; ///< default: coupled
  double rateHz = 1000;                           ///< haptic rate, Hz, in [10, 10000]
  bool realTime = true; ///< false: frames back to back (tests, benchmarks)
  /// Pause after more than this many overruns in 100 frames (-1: never), in [-1, 1e6]. nullopt
  /// (default): the device's rule, 5 for a hand on a Touch or the mouse, never for scripted and
  /// robot runs (they report overruns instead) and never for frames back to back.
  std::optional<int> overrunLimit;
  /// Session time, s, in (0, 3600]. 0 (default): the device's - scripted feed and robot: the
  /// trial's depth plus clearance at the feed rate; scripted force and hand: 2 s; trajectory: its
  /// length; touch and mouse: no limit.
  double durationS = 0;
  /// Frames to run (>= 0), replacing durationS; -1 (default): from the duration.
  int64_t maxFrames = -1;
  /// Mouse device: the foremost cutting point's starting depth below the entry point, mm
  /// (negative: above; default -2), finite.
  double mouseDepthMm = -2.0;
  /// Choose the session's resolutions and engine threads (bmSessionGrid.h): the voxmap no finer
  /// than the scene's, this machine's measured limit (the session table) and, for a CT bone, the
  /// CT's finest spacing; the shell scaled alike. false (default): the scene's. Only where the
  /// session builds its bone (BuildSession(scene, request, progress)).
  bool chooseGrid = false;
  /// With chooseGrid: the live view refreshes the cut bone meanwhile (the table's view rows;
  /// default false).
  bool liveView = false;
  /// The scene's backend's device choice (OpenCL: `bmsim devices`' number or part of a name;
  /// default "": the first usable GPU, else the first usable device).
  std::string clDevice;
};

/// A built session's parts: construct bm::HapticSession(*setup, device, options).
struct BuiltSession {
  std::unique_ptr<MachiningSetup> setup;
  std::shared_ptr<Device> device;
  /// The mouse device (also `device`) for SessionDevice::Mouse: move it with ToolPoseAtDepth.
  std::shared_ptr<ProgrammableDevice> mouse;
  SessionOptions options;
  /// Session time the frame limit stands for, s; < 0: no limit.
  double durationS = -1;
  /// How the resolutions were chosen, in words (empty: the scene's, not chosen).
  std::string gridReason;
  /// How far (mm) the scripted device's start was moved out along the axis beyond the scene's
  /// clearance so that no bone lies inside the tool there (StartLiftMm; 0: the scene's start),
  /// and that in words for the user ("" when 0).
  double startLiftMm = 0;
  std::string startNote;
};

/// Checks the request's values without building anything; throws std::invalid_argument naming
/// the field and its range.
void ValidateSessionRequest(const SessionRequest& r);

/// The session for the scene: checks the request, builds the bone (MakeSceneBone, with
/// progress; with chooseGrid at the chosen resolutions: the setup's scene holds them), the setup
/// and the device. Throws std::invalid_argument for a bad request (before
/// the bone is built) and std::runtime_error for an import or setup failure.
BuiltSession BuildSession(const Scene& scene, const SessionRequest& r,
                          const BoneProgress& progress = {});
/// As above on a bone built by the caller.
BuiltSession BuildSession(const Scene& scene, Voxmap bone, const SessionRequest& r);

/// A careful surgeon's feed for the tool at speedRpm (rpm), mm/rev: a glenoid reamer 0.2 mm/s
/// (2 mm reamed in about ten seconds), a twist drill 0.05 mm/rev (the middle of the 0.02-0.1
/// mm/rev hand drilling at 1000 rpm), a burr 0.5 mm/s. Assumptions of a steady hand, not clinical
/// measurements (Docs/Session.md, "Force scaling").
double SurgeonFeedMmPerRev(const ToolModel& tool, double speedRpm);
/// The force scale (tool N per device N) a hand on the device gets unless told otherwise: the one
/// at which kFirmPushN balances the tool's fully engaged thrust at the surgeon's feed and the
/// scene's speed (FeedBalance::FullThrust), to one significant figure (a comfort setting, not a
/// measurement), in [0.1, kMaxForceScale]. The glenoid reamer's is 50, the 2.5 mm drill's 8, the
/// skull's 2 mm burr's 0.4 (below 1 the hand feels the tool's force magnified).
double SessionForceScale(const MachiningSetup& setup);

/// Limits of the robot arm and the mouse proxy: position sources with no hand on them, held by a
/// stiff arm (2000 N/mm, up to 5 kN), so the proxy lags the commanded pose by thrust / K (0.25 mm
/// at 500 N of reaming thrust). A Touch (3.3 N) could not push a 36.5 mm reamer through cortical
/// bone at a useful feed.
DeviceLimits PositionSourceLimits();

/// The trial's final depth of the foremost cutting point below the entry point, mm: the scene's
/// depth, or full engagement of the tool's edges plus the scene's extra depth.
double TrialDepthMm(const MachiningSetup& setup);
/// Depth (mm) of the foremost cutting point of the tool at (positionMm, rotation), world, below
/// the trial's entry point along its axis (negative: above).
double ToolDepthMm(const MachiningSetup& setup, const Eigen::Vector3d& positionMm,
                   const Eigen::Matrix3d& rotation);
/// The tool's pose (world mm, tool -> world rotation) on the trial axis with its foremost cutting
/// point depthMm below the entry point (negative: above).
DevicePose ToolPoseAtDepth(const MachiningSetup& setup, double depthMm);
/// How far (mm, >= 0) the tool must move out along the trial's axis from its pose at depthMm
/// (ToolPoseAtDepth) so that no bone voxel's centre (any fill above 0) lies inside the tool by
/// more than marginMm; 0 when the pose is clear. BuildSession uses margin 0 for the scripted
/// devices' start: a tool started in bone is pushed out by the contact in its first frame, across
/// the axis as much as along it (a glenoid reamer tilted 37 deg with its rim in the face: 7.9 mm
/// sideways), and even bone within the contact's dead band pushed a tilted drill 0.01 mm. Throws
/// std::runtime_error when bone stays inside the tool at every lift up to maxLiftMm (bone above
/// the tool as well as below it).
double StartLiftMm(MachiningSetup& setup, double depthMm, double marginMm, double maxLiftMm = 50.0);

} // namespace bm
