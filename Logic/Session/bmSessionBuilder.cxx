// bmSessionBuilder.cxx - see bmSessionBuilder.h.
#include "bmSessionBuilder.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "bmEdgeQuadrature.h"
#include "bmFeedBalance.h"
#include "bmToolModel.h"
#include "bmTouchDevice.h"
#include "bmVirtualCoupling.h"
#include "bmCheckRange.h"

namespace bm {

namespace {

/// Where a Touch's workspace centre sits above the entry point along the axis, mm.
constexpr double kTouchCentreAboveEntryMm = 10.0;
/// Scripted force and hand runs last this long unless the request says otherwise, s.
constexpr double kPushDurationS = 2.0;

} // namespace

const char* ToString(SessionDevice d) {
  switch (d) {
  case SessionDevice::Scripted:
    return "scripted";
  case SessionDevice::Robot:
    return "robot";
  case SessionDevice::Touch:
    return "touch";
  case SessionDevice::Mouse:
    return "mouse";
  }
  return "?";
}

SessionDevice SessionDeviceFromString(const std::string& s) {
  for (SessionDevice d :
       {SessionDevice::Scripted, SessionDevice::Robot, SessionDevice::Touch, SessionDevice::Mouse})
    if (s == ToString(d))
      return d;
  throw std::invalid_argument("the session device must be scripted, robot, touch or mouse, not '" +
                              s + "'");
}

DeviceLimits PositionSourceLimits() {
  DeviceLimits l;
  l.maxForceN = 5000;
  l.maxStiffnessNPerMm = 2000;
  l.maxDampingNsPerMm = 2.0;
  l.workspaceRadiusMm = 1000;
  return l;
}

double TrialDepthMm(const MachiningSetup& setup) {
  const TrialSpec& t = setup.GetScene().trial;
  return t.depthMm >= 0 ? t.depthMm : FullEngagementDepth(setup.Tool()) + t.extraDepthMm;
}

double ToolDepthMm(const MachiningSetup& setup, const Eigen::Vector3d& positionMm,
                   const Eigen::Matrix3d& rotation) {
  const TrialSpec& t = setup.GetScene().trial;
  const Eigen::Vector3d tip =
      positionMm + rotation * Eigen::Vector3d(0, 0, ForemostCuttingZ(setup.Tool()));
  return (t.entry - tip).dot(t.axis.normalized());
}

DevicePose ToolPoseAtDepth(const MachiningSetup& setup, double depthMm) {
  const TrialSpec& t = setup.GetScene().trial;
  DevicePose pose;
  pose.rotation = setup.ToolRotation();
  pose.positionMm = t.entry - t.axis.normalized() * depthMm -
                    pose.rotation * Eigen::Vector3d(0, 0, ForemostCuttingZ(setup.Tool()));
  return pose;
}

double StartLiftMm(MachiningSetup& setup, double depthMm, double marginMm, double maxLiftMm) {
  const ToolModel& tool = setup.Tool();
  const Voxmap& bone = setup.Bone();
  const DevicePose start = ToolPoseAtDepth(setup, depthMm);
  const Eigen::Matrix3d& R = start.rotation;
  const Eigen::Vector3d axis = R.col(2);
  const double radius = tool.OuterRadius(), h = bone.Spacing();
  const std::array<double, 2> zRange = tool.AxialRange();
  const auto& dims = bone.Dims();
  const auto& origin = bone.Origin(); // the centre of voxel (0, 0, 0)
  // The tool shrunk by the margin: at radius rho, the inside interval of z that holds a ball of
  // radius marginMm (the intervals at rho and rho + margin, each narrowed by it).
  const auto shrunk = [&](double rho, double& lo, double& hi) {
    double lo1, hi1, lo2, hi2;
    if (rho + marginMm > radius || !tool.ZRange(rho, lo1, hi1) ||
        !tool.ZRange(rho + marginMm, lo2, hi2))
      return false;
    lo = std::max(lo1, lo2) + marginMm;
    hi = std::min(hi1, hi2) - marginMm;
    return lo <= hi;
  };
  double lift = 0;
  for (int pass = 0; pass < 64; ++pass) {
    const Eigen::Vector3d p = start.positionMm + axis * lift;
    // The voxels in the box of the tool's cylinder at this lift.
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double e = radius * std::sqrt(std::max(0.0, 1.0 - axis(a) * axis(a)));
      const double c0 = p(a) + zRange[0] * axis(a), c1 = p(a) + zRange[1] * axis(a);
      lo[a] = std::max(0, int(std::floor((std::min(c0, c1) - e - origin[size_t(a)]) / h)));
      hi[a] = std::min(dims[size_t(a)] - 1,
                       int(std::ceil((std::max(c0, c1) + e - origin[size_t(a)]) / h)));
    }
    double need = 0;
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          if (bone.GetFill(bone.Index(i, j, k)) <= 0)
            continue;
          const Eigen::Vector3d q =
              R.transpose() *
              (Eigen::Vector3d(origin[0] + i * h, origin[1] + j * h, origin[2] + k * h) - p);
          double zLo, zHi;
          if (!shrunk(std::hypot(q(0), q(1)), zLo, zHi) || q(2) < zLo || q(2) > zHi)
            continue;
          need = std::max(need, q(2) - zLo); // out by this much, it is below the shrunk tool
        }
    if (need == 0)
      return lift;
    lift += need + 1e-3 * h;
    if (lift > maxLiftMm)
      break;
  }
  std::ostringstream m;
  m << "the tool cannot start clear of the bone: moved out along its axis up to " << maxLiftMm
    << " mm from the scene's start, bone stays inside it (bone above the tool as well as below "
       "it: check the entry point and the axis)";
  throw std::runtime_error(m.str());
}

double SurgeonFeedMmPerRev(const ToolModel& tool, double speedRpm) {
  if (!(speedRpm > 0))
    throw std::invalid_argument("a surgeon's feed needs a positive spindle speed (rpm)");
  const std::string kind = tool.Kind();
  if (kind == "drill")
    return 0.05;
  const double mmPerS = kind == "reamer" ? 0.2 : 0.5;
  return mmPerS * 60.0 / speedRpm;
}

double SessionForceScale(const MachiningSetup& setup) {
  const double n = setup.GetScene().trial.speedRpm;
  FeedBalance balance(setup.Tool(), setup.Model());
  const double thrust = balance.FullThrust(SurgeonFeedMmPerRev(setup.Tool(), n), n);
  double s = thrust / kFirmPushN;
  if (!(s > 0))
    return 1.0;
  const double unit = std::pow(10.0, std::floor(std::log10(s))); // one significant figure
  s = std::round(s / unit) * unit;
  return std::clamp(s, 0.1, kMaxForceScale);
}

void ValidateSessionRequest(const SessionRequest& r) {
  const bool scripted = r.device == SessionDevice::Scripted;
  if (r.device == SessionDevice::Robot && r.mode != ScriptMode::Feed)
    throw std::invalid_argument(std::string("a robot session only feeds; mode '") +
                                ToString(r.mode) + "' needs the scripted device");
  if (scripted && (r.mode == ScriptMode::Force || r.mode == ScriptMode::Hand))
    CheckRange("the applied force (N at the device)", r.appliedForceN, 0.0,
               DeviceLimits().maxForceN);
  if (scripted && r.mode == ScriptMode::Hand)
    CheckRange("the hand's tremor (N at the device)", r.handTremorN, 0.0, DeviceLimits().maxForceN);
  if (scripted && r.mode == ScriptMode::Trajectory && r.trajectory.empty())
    throw std::invalid_argument("a trajectory session needs trajectory samples");
  if (r.forceScale != 0)
    CheckRange("the force scale (tool N per device N)", r.forceScale, 1e-3, kMaxForceScale);
  CheckRange("the haptic rate (Hz)", r.rateHz, 10, 10000);
  if (r.overrunLimit)
    CheckRange("the overrun limit (frames in 100)", *r.overrunLimit, -1, 1e6);
  if (r.durationS != 0)
    CheckRange("the session duration (s)", r.durationS, 1e-3, 3600);
  if (r.maxFrames < -1)
    throw std::invalid_argument("the frame limit must be >= 0 (or -1: from the duration), not " +
                                std::to_string(r.maxFrames));
  if (r.device == SessionDevice::Mouse && !std::isfinite(r.mouseDepthMm))
    throw std::invalid_argument("the mouse proxy's depth must be finite (mm)");
  // A hand on a device feels the sampled virtual coupling, which is passive (cannot pump energy
  // into the hand and grow unstable) only while its damping exceeds K T / 2 (Colgate and
  // Schenkel). The damping is K T up to the device's nominal damping, so below K / (2 B_max) a
  // scripted hand pushes through the bone unopposed (at 10 Hz on a Touch it went 190 mm): refused
  // by name. A robot or the mouse is a position source, not a hand. The Touch's published limits
  // are the scripted hand's and the Touch's before it reports its own.
  const bool handHeld = r.device == SessionDevice::Touch ||
                        (scripted && (r.mode == ScriptMode::Force || r.mode == ScriptMode::Hand));
  if (handHeld) {
    CouplingOptions co; // the check below does not depend on the scale: K and B scale together
    co.forceScale = r.forceScale != 0 ? r.forceScale : 1.0;
    const double periodS = 1.0 / r.rateHz;
    const VirtualCoupling c(co, DeviceLimits(), periodS);
    if (!(c.Damping() > 0.5 * c.Stiffness() * periodS)) {
      std::ostringstream m;
      m << "the haptic rate " << r.rateHz << " Hz is too low for a hand on the device: its "
        << "coupling (" << c.Stiffness() / co.forceScale << " N/mm, damping "
        << c.Damping() / co.forceScale << " N s/mm at the device) is passive only above "
        << std::ceil(c.Stiffness() / (2 * c.Damping())) << " Hz (damping > stiffness x period / 2)";
      throw std::invalid_argument(m.str());
    }
  }
}

BuiltSession BuildSession(const Scene& scene, const SessionRequest& r,
                          const BoneProgress& progress) {
  ValidateSessionRequest(r);
  if (!r.chooseGrid)
    return BuildSession(scene, MakeSceneBone(scene, progress), r);
  // The measured limit first (it caps the import's resolution), then the CT's spacing where the
  // CT is read; the shell follows the voxmap the import made.
  const std::vector<SessionAccuracyRow> accuracy = LoadDefaultSessionAccuracy();
  const SessionGridPlan plan =
      PlanSessionGrid(scene, LoadDefaultSessionTable(), r.liveView, r.rateHz, accuracy);
  const double toolVoxel = ToolVoxelMm(MakeTool(scene.tool)->OuterRadius());
  Voxmap bone = MakeSceneBone(plan.scene, progress, true, toolVoxel);
  Scene chosen = plan.scene;
  std::string reason = plan.reason;
  const auto& d = bone.Dims();
  const int cells = std::max({d[0], d[1], d[2]});
  if (scene.bone.type != "block" && cells < chosen.voxmapResolution) {
    const int threads = chosen.threads;
    chosen = chosen.WithVoxmapResolution(cells);
    chosen.threads = threads;
    std::ostringstream why;
    why << "; the bone as imported has " << cells << " cells of " << bone.Spacing()
        << " mm (no finer than the CT's spacing, unless the tool needs " << toolVoxel << " mm)";
    const std::string bought = AccuracyBought(accuracy, scene.name, cells);
    why << "; "
        << (bought.empty() ? "no accuracy measured at voxmap " + std::to_string(cells)
                           : "at voxmap " + std::to_string(cells) + ", " + bought);
    reason += why.str();
  }
  BuiltSession b = BuildSession(chosen, std::move(bone), r);
  std::ostringstream head;
  head << "voxmap " << chosen.voxmapResolution << ", shell " << chosen.shellResolution << ", "
       << chosen.threads << " engine thread" << (chosen.threads == 1 ? "" : "s") << ": ";
  b.gridReason = head.str() + reason;
  return b;
}

BuiltSession BuildSession(const Scene& scene, Voxmap bone, const SessionRequest& r) {
  ValidateSessionRequest(r);
  BuiltSession b;
  b.setup = std::make_unique<MachiningSetup>(scene, std::move(bone), r.clDevice);
  const MachiningSetup& setup = *b.setup;
  const TrialSpec& t = setup.GetScene().trial;
  const Eigen::Vector3d axis = t.axis.normalized();
  SessionOptions& o = b.options;
  o.rateHz = r.rateHz;
  o.realTime = r.realTime;
  o.proxy.method = r.contact;
  o.proxy.rendering = r.rendering;
  const bool positionSource = r.device == SessionDevice::Robot || r.device == SessionDevice::Mouse;
  o.proxy.coupling.forceScale = r.forceScale != 0 ? r.forceScale
                                : positionSource  ? 1.0
                                                  : SessionForceScale(setup);
  // The overrun pause protects a hand on a device; a scripted or robot run reports its overruns
  // instead, and frames back to back have no period to overrun.
  const bool hand = r.device == SessionDevice::Touch || r.device == SessionDevice::Mouse;
  o.overrunLimit = r.overrunLimit ? *r.overrunLimit : (hand && r.realTime ? 5 : -1);

  // The feed's length: from clearance above the entry to the trial's depth.
  const double feedS = (TrialDepthMm(setup) + t.clearanceMm) / (t.feedMmPerRev * t.speedRpm / 60.0);
  double duration = -1;
  switch (r.device) {
  case SessionDevice::Touch: {
    b.device = std::make_shared<TouchDevice>();
    o.deviceOffsetMm = t.entry + axis * kTouchCentreAboveEntryMm;
    break;
  }
  case SessionDevice::Mouse: {
    b.mouse = std::make_shared<ProgrammableDevice>(PositionSourceLimits());
    b.mouse->SetPose(ToolPoseAtDepth(setup, r.mouseDepthMm));
    // A depth step (a wheel click, a typed depth) reaches the tool over frames, at 20 mm/s, and
    // the tool cuts it at the scene's feed, a surgeon's: the stiff arm behind the mouse would
    // otherwise drive every notch at the force model's largest feed, ten times the scene's
    // force for the frames the notch takes (a wheel click, or a depth moved while paused).
    b.mouse->SetMaxSpeed(20.0);
    o.proxy.maxFeedMmPerRev = std::min(o.proxy.maxFeedMmPerRev, t.feedMmPerRev);
    b.device = b.mouse;
    break;
  }
  case SessionDevice::Scripted:
  case SessionDevice::Robot: {
    ScriptedDeviceOptions d;
    d.mode = r.device == SessionDevice::Robot ? ScriptMode::Feed : r.mode;
    // Never inside bone: a start the bone reaches into is moved out along the axis (the contact
    // would push the tool out sideways in the first frame), and the feed starts from there.
    b.startLiftMm = StartLiftMm(*b.setup, -t.clearanceMm, 0.0);
    if (b.startLiftMm > 0) {
      std::ostringstream note;
      note << std::fixed << std::setprecision(2) << "the tool starts " << b.startLiftMm
           << " mm further out along its axis than the scene's clearance of " << t.clearanceMm
           << " mm: bone lay inside it there";
      b.startNote = note.str();
    }
    d.startMm = ToolPoseAtDepth(setup, -t.clearanceMm - b.startLiftMm).positionMm;
    d.axis = axis;
    d.rotation = setup.ToolRotation();
    d.feedMmPerRev = t.feedMmPerRev;
    d.speedRpm = t.speedRpm;
    d.appliedForceN = r.appliedForceN;
    d.handTremorN = r.handTremorN;
    d.handSeed = r.handSeed;
    d.stopAtBreakthrough = r.stopAtBreakthrough;
    d.trajectory = r.trajectory;
    if (positionSource)
      d.limits = PositionSourceLimits();
    b.device = std::make_shared<ScriptedDevice>(d);
    duration = d.mode == ScriptMode::Feed
                   ? feedS + b.startLiftMm / (t.feedMmPerRev * t.speedRpm / 60.0)
               : d.mode == ScriptMode::Trajectory ? r.trajectory.back().timeS
                                                  : kPushDurationS;
    break;
  }
  }
  if (r.durationS > 0)
    duration = r.durationS;
  if (r.maxFrames >= 0) {
    o.maxFrames = r.maxFrames;
    b.durationS = double(r.maxFrames) / o.rateHz;
  } else if (duration > 0) {
    o.maxFrames = int64_t(std::ceil(duration * o.rateHz));
    b.durationS = duration;
  }
  return b;
}

} // namespace bm
