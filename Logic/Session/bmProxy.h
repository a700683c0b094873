// bmProxy.h - the simulated tool behind the virtual coupling: one haptic frame of the interaction
// model (Docs/Interaction.md).
//
// Methods (ContactMethod), each rendered through the coupling (Rendering::Coupled) or, to show
// why the coupling is needed, directly (Rendering::Direct):
//  - Cutting (ours, section 4). Spindle running: along the tool axis the proxy advances by the u
//    at which the engine's thrust balances the axial coupling force (bmFeedBalance.h); the engine
//    (bmEngine.h) cuts the swept voxels at that feed and reports thrust, torque and lateral force;
//    across the axis the bone is a rigid contact (Kim et al.'s point shell against the tool's
//    distance field, with a dead band of ~1 voxel for the wall the engine is still thinning),
//    solved with the axis held. Before any cutting element touches bone, the proxy moves freely
//    toward the device but stops at first contact of a surface facing the feed (swept in steps
//    of at most half a voxel; ToolPart::Leading): the flank of a drill in its own hole, beside the
//    partial-volume wall, slides along it as it does while cutting.
//    Non-cutting surfaces that lead the feed (a reamer's guide nipple; ToolPart::NonCuttingLeading)
//    are a rigid contact along the axis too: the advance, cutting or free, stops at their first
//    contact with bone and does not go deeper while they touch it, so the device's push is
//    rendered through the coupling. Bone beside such a part (within the dead band of its rim, a
//    partial-volume hole wall along the nipple) is across the axis and does not stop it. The
//    engine removes with the whole envelope (Docs/Model.md section 5), so the nipple removes at
//    most the graze of the sub-step that found the contact.
//    Spindle stopped: every surface is a rigid contact (same solve, all three axes).
//    Direct: the penalty force k_dev * (deepest penetration) along the contact normal at the
//    device pose, plus the engine's force at the device's own feed (a damper with a wall).
//  - KimPark (section 3). Coupled: the proxy solves the linearised equilibrium F_c + F_vc +
//    (dF_c/dx + dF_vc/dx) dx = 0 (3x3) each iteration, steps limited to half a voxel, and with the
//    spindle running removes, Boolean, the voxels whose centre lies more than half a voxel inside
//    it (their flood fill). Direct: F_c at the device pose (their Fig. 3 failure).
//
// The proxy never tunnels: every motion of the proxy toward bone is swept in sub-steps of at most
// half a voxel (maxStepVoxels), stopping at first contact; the equilibrium solve also limits its
// steps to that length. While cutting, the advance per frame is also bounded by the largest feed
// (maxFeedMmPerRev), so no frame cuts at a feed the force model does not cover. Orientation follows
// the device (3-DoF force output, like the Touch). With a force scale s (CouplingOptions) the
// coupling works in tool units and the device is sent the tool force / s.
//
// Units: world mm, N, N mm, rpm, mm/rev, s.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "bmBoneSurfaceShell.h"
#include "bmFeedBalance.h"
#include "bmKimParkContact.h"
#include "bmMachiningSetup.h"
#include "bmToolDistanceField.h"
#include "bmVirtualCoupling.h"

namespace bm {

enum class ContactMethod { Cutting, KimPark };
enum class Rendering { Coupled, Direct };
const char* ToString(ContactMethod m);
const char* ToString(Rendering r);
/// "cutting"|"kim"; "coupled"|"direct". Throw std::invalid_argument otherwise.
ContactMethod ContactMethodFromString(const std::string& s);
Rendering RenderingFromString(const std::string& s);

struct ProxyOptions {
  ContactMethod method = ContactMethod::Cutting;
  Rendering rendering = Rendering::Coupled;
  CouplingOptions coupling;              ///< K, B (defaults: device nominal K, B = K T)
  double contactStiffnessPerArea = 2000; ///< k_A of the rigid contact, N/mm^3
  int sdfResolution = 256;    ///< tool distance field: cells along the tool's longest side
  double maxStepVoxels = 0.5; ///< longest proxy step toward bone, voxels
  int maxIterations = 24;     ///< equilibrium iterations per frame
  /// The equilibrium solve stops once its step is shorter than this, mm (default 1e-6: a
  /// nanometre moves the device force by micronewtons; a seated reamer's solve then takes two
  /// contact queries where it took three, each over thousands of points in contact).
  double relaxToleranceMm = 1e-6;
  double deadBandVoxels = 1.0; ///< Cutting: lateral contact dead band, voxels
  /// Cutting, coupled: points deeper than this inside the tool whose voxel holds less than 5 % of
  /// its bone do not push (voxels, default 6: the dead band and five voxels; 0 = no
  /// cap). They are slivers the spinning envelope swept through and the engine's removal left;
  /// fuller voxels that deep still push, so nothing tunnels (KimParkContact::SetDepthCap,
  /// Docs/Interaction.md).
  double contactDepthCapVoxels = 6.0;
  /// Cutting: the largest feed the proxy cuts at, mm/rev (default 1.0, the top of the feed-balance
  /// table). It bounds the advance per frame to f n T / 60, so that a device far ahead of the proxy
  /// (a resume after a move, a mouse depth step) is followed over frames at a feed the force model
  /// covers, and the engaged fraction changes little within a frame.
  double maxFeedMmPerRev = 1.0;
  double kimCutDepthVoxels = 0.5; ///< KimPark: removal depth inside the tool, voxels
  /// Contact queries within this distance (voxels) of the pose where the contact last gathered its
  /// candidate points, at the same orientation and with the shell unchanged, read only those
  /// candidates (KimParkContact::SetCandidateRadius; exact, only faster); 0 = scan every query.
  double candidateRadiusVoxels = 2.0;
  /// Sweeps ask only whether a sub-step touches bone, stopping at the first point in contact
  /// (KimParkContact::Touches; default). false: the reference, a full contact query per sub-step
  /// (the same frames bit for bit, slower: after breakthrough the drill's tip meets tens of
  /// thousands of points, Docs/Performance.md "Drilling through the plate").
  bool sweepFirstContact = true;
  /// Cutting: across the axis the engine's lateral cutting force acts on the proxy averaged over
  /// this many spindle revolutions (an exponential mean with time constant revolutions x 60 / n;
  /// default 1; 0 = each frame's own force). Docs/Interaction.md, "Across the axis while cutting".
  double lateralAverageRevolutions = 1.0;
};

/// One frame's result.
struct ProxyFrame {
  Eigen::Vector3d devicePositionMm =
      Eigen::Vector3d::Zero(); ///< tool pose the device asks for, world mm
  Eigen::Vector3d proxyPositionMm = Eigen::Vector3d::Zero(); ///< simulated tool, world mm
  Eigen::Vector3d couplingForceN =
      Eigen::Vector3d::Zero(); ///< on the proxy (direct: on the tool), N
  Eigen::Vector3d deviceForceN =
      Eigen::Vector3d::Zero(); ///< what the device is sent: finite, clamped, N
  Eigen::Vector3d lateralForceN =
      Eigen::Vector3d::Zero(); ///< cutting force across the axis, world N
  double feedMmPerRev = 0;     ///< feed this frame, mm/rev (0 when not cutting)
  double thrustN = 0;          ///< cutting thrust (KimPark: axial contact force), N
  double torqueNmm = 0;        ///< resisting torque, N mm (KimPark: 0, the method has none)
  int64_t removedVoxels = 0;   ///< voxels taken to void this frame
  double removedVolumeMm3 = 0;
  int contactPoints = 0; ///< bone points in contact
  bool clamped = false;  ///< the device force was limited to the maximum
};

class Proxy {
public:
  /// setup: the scene's tool, model, bone and engine (must outlive the proxy); limits: the
  /// device's; frameS: the haptic period, s. Builds the tool distance field and the bone surface
  /// shell.
  Proxy(MachiningSetup& setup, const DeviceLimits& limits, double frameS,
        const ProxyOptions& o = {});
  ~Proxy();
  /// Advances one frame to the device's tool pose (world mm, tool -> world rotation) at spindle
  /// speed speedRpm (0 = stopped). The first call places the proxy at the device.
  ProxyFrame Step(const Eigen::Vector3d& deviceMm, const Eigen::Matrix3d& rotation,
                  double speedRpm);
  /// Warm-up before the haptic loop: the feed-balance table for speedRpm (rpm) and one engine
  /// frame that touches nothing (the backend's first-frame costs). Default: not needed for
  /// correctness, only for the first frames' timing.
  void Prepare(double speedRpm);
  /// Places the proxy at the device again (no force) on the next Step.
  void Reset() { Started_ = false; }
  /// Keeps the proxy (and the cut) but forgets the device's last position, so that a device that
  /// moved while the session was paused gives no velocity spike on the next Step.
  void ForgetDeviceMotion() { ForgetMotion_ = true; }
  const VirtualCoupling& Coupling() const { return Coupling_; }
  const ProxyOptions& Options() const { return O_; }
  const BoneSurfaceShell& SurfaceShell() const { return *Shell_; }
  const Eigen::Vector3d& Position() const { return P_; }

private:
  /// Moves from `from` toward `to` (world mm) in steps of at most maxStepVoxels and returns the
  /// first position where `part` of the tool touches bone beyond `band` (mm), or `to`. A part
  /// other than the whole tool counts bone only inside its rim less the lateral dead band (bone
  /// beside it is across the axis); the non-cutting leading part, already on bone at `from`,
  /// stays there (rigid).
  Eigen::Vector3d Sweep(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                        const Eigen::Matrix3d& R, double band,
                        ToolPart part = ToolPart::Whole) const;
  /// Whether `part` of the tool at (R, p) touches bone beyond band (mm), counting bone at least
  /// rim (mm) inside the part's rim: Touches, or the full query's count (sweepFirstContact off).
  bool Touches(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double band, ToolPart part,
               double rim) const;
  Eigen::Vector3d Relax(Eigen::Vector3d p, const Eigen::Vector3d& xd, const Eigen::Vector3d& vd,
                        const Eigen::Matrix3d& R, double band, const Eigen::Vector3d* lockAxis,
                        const Eigen::Vector3d& extra, ContactResult& last) const;
  void CuttingStep(const Eigen::Vector3d& xd, const Eigen::Vector3d& vd, const Eigen::Matrix3d& R,
                   double n, ProxyFrame& f);
  void SyncShell(const Eigen::Matrix3d& R, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

  MachiningSetup& Setup_;
  ProxyOptions O_;
  double T_;
  VirtualCoupling Coupling_;
  std::unique_ptr<ToolDistanceField> Sdf_;
  std::unique_ptr<BoneSurfaceShell> Shell_;
  std::unique_ptr<KimParkContact> Contact_;
  FeedBalance Balance_;
  bool Started_ = false, ForgetMotion_ = false;
  Eigen::Vector3d P_ = Eigen::Vector3d::Zero(), Xd_ = Eigen::Vector3d::Zero();
  double Fraction_ = 0; // engaged fraction from the last engine frame
  Eigen::Vector3d LateralMean_ = Eigen::Vector3d::Zero(); // revolution-averaged lateral force, N
  double SpindleAngle_ = 0;                               // rad
};

} // namespace bm
