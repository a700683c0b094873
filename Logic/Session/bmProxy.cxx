#include "bmProxy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/LU>

namespace bm {

const char* ToString(ContactMethod m) {
  return m == ContactMethod::Cutting ? "cutting" : "kim";
}
const char* ToString(Rendering r) {
  return r == Rendering::Coupled ? "coupled" : "direct";
}

ContactMethod ContactMethodFromString(const std::string& s) {
  if (s == "cutting")
    return ContactMethod::Cutting;
  if (s == "kim")
    return ContactMethod::KimPark;
  throw std::invalid_argument("contact method must be cutting or kim, not '" + s + "'");
}

Rendering RenderingFromString(const std::string& s) {
  if (s == "coupled")
    return Rendering::Coupled;
  if (s == "direct")
    return Rendering::Direct;
  throw std::invalid_argument("rendering must be coupled or direct, not '" + s + "'");
}

Proxy::Proxy(MachiningSetup& setup, const DeviceLimits& limits, double frameS,
             const ProxyOptions& o)
    : Setup_(setup), O_(o), T_(frameS), Coupling_(o.coupling, limits, frameS),
      Balance_(setup.Tool(), setup.Model()) {
  if (!(frameS > 0))
    throw std::invalid_argument("proxy: frame period must be > 0");
  if (!(o.maxFeedMmPerRev > 0))
    throw std::invalid_argument("proxy: the largest feed must be > 0 mm/rev");
  if (!(o.lateralAverageRevolutions >= 0 && o.lateralAverageRevolutions <= 100))
    throw std::invalid_argument(
        "proxy: the lateral force's averaging must be in [0, 100] revolutions");
  Sdf_ = std::make_unique<ToolDistanceField>(setup.Tool(), o.sdfResolution);
  Shell_ = std::make_unique<BoneSurfaceShell>(setup.Bone());
  Contact_ = std::make_unique<KimParkContact>(*Sdf_, *Shell_, o.contactStiffnessPerArea);
  Contact_->SetCandidateRadius(o.candidateRadiusVoxels * setup.Bone().Spacing());
  if (o.method == ContactMethod::Cutting && o.rendering == Rendering::Coupled &&
      o.contactDepthCapVoxels > 0)
    Contact_->SetDepthCap(o.contactDepthCapVoxels * setup.Bone().Spacing());
}

Proxy::~Proxy() = default;

void Proxy::Prepare(double speedRpm) {
  if (speedRpm > 0)
    Balance_.FullThrust(0.02, speedRpm);
  // One engine frame far from the bone: no element is engaged and nothing is removed.
  FrameInput in;
  in.position = Eigen::Vector3d(1e6, 1e6, 1e6);
  in.removeMaterial = false;
  in.speedRpm = speedRpm > 0 ? speedRpm : 1000;
  Setup_.GetEngine().Step(in);
}

Eigen::Vector3d Proxy::Sweep(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                             const Eigen::Matrix3d& R, double band, ToolPart part) const {
  const Eigen::Vector3d d = to - from;
  const double L = d.norm();
  if (L <= 0 || !Sdf_->Has(part))
    return to;
  Eigen::Vector3d lo0, hi0, lo1, hi1;
  Contact_->ToolBox(R, from, lo0, hi0, part);
  Contact_->ToolBox(R, to, lo1, hi1, part);
  if (Shell_->EmptyIn(lo0.cwiseMin(lo1), hi0.cwiseMax(hi1)))
    return to; // no bone anywhere near the path
  // A part's rim gets the lateral dead band: bone beside it is across the axis, not in front.
  const double rim = part == ToolPart::Whole ? 0.0 : O_.deadBandVoxels * Setup_.Bone().Spacing();
  if (part == ToolPart::NonCuttingLeading && Touches(R, from, band, part, rim))
    return from; // a rigid part on bone goes no deeper
  const double step = O_.maxStepVoxels * Setup_.Bone().Spacing();
  const int n = std::max(1, int(std::ceil(L / step)));
  // In runs of kRun steps: a run whose part boxes hold no bone point is passed without a query
  // (every query there would find none), so a tool falling through its own hole after
  // breakthrough crosses the open space at once, not half a voxel per query.
  constexpr int kRun = 16;
  for (int first = 1; first <= n; first += kRun) {
    const int last = std::min(n, first + kRun - 1);
    Contact_->ToolBox(R, from + d * (double(first) / n), lo0, hi0, part);
    Contact_->ToolBox(R, from + d * (double(last) / n), lo1, hi1, part);
    if (Shell_->EmptyIn(lo0.cwiseMin(lo1), hi0.cwiseMax(hi1)))
      continue;
    for (int i = first; i <= last; ++i) {
      const Eigen::Vector3d q = from + d * (double(i) / n);
      if (Touches(R, q, band, part, rim))
        return q; // first contact: at most one step deep
    }
  }
  return to;
}

bool Proxy::Touches(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double band, ToolPart part,
                    double rim) const {
  return O_.sweepFirstContact ? Contact_->Touches(R, p, band, part, rim)
                              : Contact_->Query(R, p, band, part, rim).points > 0;
}

Eigen::Vector3d Proxy::Relax(Eigen::Vector3d p, const Eigen::Vector3d& xd,
                             const Eigen::Vector3d& vd, const Eigen::Matrix3d& R, double band,
                             const Eigen::Vector3d* lockAxis, const Eigen::Vector3d& extra,
                             ContactResult& last) const {
  const double K = Coupling_.Stiffness(), B = Coupling_.Damping(), Kc = K + B / T_;
  const Eigen::Matrix3d P =
      lockAxis ? Eigen::Matrix3d(Eigen::Matrix3d::Identity() - *lockAxis * lockAxis->transpose())
               : Eigen::Matrix3d::Identity();
  const double maxStep = O_.maxStepVoxels * Setup_.Bone().Spacing();
  for (int it = 0; it < O_.maxIterations; ++it) {
    last = Contact_->Query(R, p, band);
    const Eigen::Vector3d fvc = Coupling_.Force(xd, vd, p, (p - P_) / T_);
    const Eigen::Vector3d r = P * (last.force + fvc + extra);
    if (r.norm() < 1e-9)
      break;
    if (last.points == 0) {
      // Free: the coupling force is linear in p with slope -Kc; sweep to its zero, stop at contact.
      const Eigen::Vector3d target = p + r / Kc;
      const Eigen::Vector3d q = Sweep(p, target, R, band);
      p = q;
      if ((q - target).norm() < 1e-12) {
        last = ContactResult{};
        break;
      }
      continue;
    }
    Eigen::Matrix3d A = P * (last.jacobian - Kc * Eigen::Matrix3d::Identity()) * P;
    if (lockAxis)
      A += *lockAxis * lockAxis->transpose();
    Eigen::Vector3d dx = P * A.fullPivLu().solve(-r);
    if (!dx.allFinite())
      break;
    const double n = dx.norm();
    if (n > maxStep)
      dx *= maxStep / n;
    p += dx;
    if (n < O_.relaxToleranceMm)
      break;
  }
  return p;
}

void Proxy::SyncShell(const Eigen::Matrix3d& R, const Eigen::Vector3d& a,
                      const Eigen::Vector3d& b) {
  Eigen::Vector3d lo0, hi0, lo1, hi1;
  Contact_->ToolBox(R, a, lo0, hi0);
  Contact_->ToolBox(R, b, lo1, hi1);
  Shell_->Sync(lo0.cwiseMin(lo1), hi0.cwiseMax(hi1));
}

void Proxy::CuttingStep(const Eigen::Vector3d& xd, const Eigen::Vector3d& vd,
                        const Eigen::Matrix3d& R, double n, ProxyFrame& f) {
  const double K = Coupling_.Stiffness(), B = Coupling_.Damping(), Kc = K + B / T_;
  const Eigen::Vector3d a = R.col(2); // tool axis, out of the bone
  const double h = Setup_.Bone().Spacing();
  const double maxStep = O_.maxStepVoxels * h;
  // Axial: the advance u along -a.
  const double f0 = -a.dot(K * (xd - P_) + B * vd);
  double u = 0;
  bool cutting = false; // the advance is a cut (feed balance), not a free approach
  Eigen::Vector3d p = P_;
  if (f0 <= 0) {
    u = f0 / Kc; // pulled out: follow the coupling's zero (the hole behind is open)
    p = P_ - u * a;
  } else {
    if (Fraction_ > 0)
      p = P_ - Balance_.SolveAdvance(Fraction_, f0, Kc, n, T_,
                                     std::min(maxStep, O_.maxFeedMmPerRev * n * T_ / 60.0)) *
                   a;
    else // free: the advance meets bone only with the surfaces that face the feed
      p = Sweep(P_, P_ - (f0 / Kc) * a, R, 0.0, ToolPart::Leading);
    // Leading non-cutting surfaces are a rigid contact: the advance stops where they meet bone.
    p = Sweep(P_, p, R, 0.0, ToolPart::NonCuttingLeading);
    u = (P_ - p).dot(a);
    cutting = Fraction_ > 0 && u > 0;
  }
  // The engine cuts along the advance at the balancing feed. When not cutting (retracting, or
  // approaching until first contact) it runs at a tiny feed without removal, so that it still
  // reports the engaged fraction for the next frame.
  const double feed = cutting ? 60.0 * u / (n * T_) : 0.0;
  FrameInput in;
  in.rotation = R;
  in.position = p;
  in.motion = p - P_;
  in.feedMmPerRev = std::max(feed, Balance_.MinFeed());
  in.speedRpm = n;
  SpindleAngle_ = std::fmod(SpindleAngle_ + 2 * 3.14159265358979323846 * n / 60.0 * T_,
                            2 * 3.14159265358979323846);
  in.spindleAngle = SpindleAngle_;
  in.removeMaterial = cutting;
  // The whole envelope removes (Docs/Model.md section 5), as in feed trials: lips-only removal
  // leaves the grid-aliasing remnants in front of the face (the glenoid session at voxmap 64
  // stalled at 1.2 of its 2 mm). The rigid nipple removes no more than the last sub-step's graze
  // (above).
  in.envelopeRemoves = true;
  const FrameResult r = Setup_.GetEngine().Step(in);
  const double full = Balance_.FullThrust(in.feedMmPerRev, n);
  Fraction_ = full > 0 ? std::clamp(r.thrustN / full, 0.0, 2.0) : 0.0;
  // The feed the forces were computed at: an advance shorter than the feed balance's least feed
  // (the last hundredth of a mouse notch, say) is cut at that feed, and the frame says so.
  f.feedMmPerRev = feed > 0 ? in.feedMmPerRev : 0.0;
  f.thrustN = feed > 0 ? r.thrustN : 0.0;
  f.torqueNmm = feed > 0 ? r.torqueNmm : 0.0;
  f.removedVoxels = r.removedVoxels;
  f.removedVolumeMm3 = r.removedVolumeMm3;
  const Eigen::Vector3d lateral =
      feed > 0 ? Eigen::Vector3d(R * Eigen::Vector3d(r.forceTool(0), r.forceTool(1), 0))
               : Eigen::Vector3d::Zero();
  f.lateralForceN = lateral;
  // The lateral force acts averaged over the spindle's revolution: frame by frame it is mostly the
  // voxel grid's aliasing of a partly engaged face (tens of N either way for a reamer a tenth of a
  // voxel off centre), and acting at once it made the massless proxy whirl about the axis inside
  // the guide pin's hole, ~1 mm per frame (Docs/Interaction.md).
  const double tau = O_.lateralAverageRevolutions * 60.0 / n;
  LateralMean_ += (tau > 0 ? T_ / (tau + T_) : 1.0) * (lateral - LateralMean_);
  if (r.removedVoxels > 0)
    SyncShell(R, P_, p);
  // Across the axis: rigid contact with the axis held, the averaged lateral cutting force acting
  // too.
  ContactResult c;
  p = Relax(p, xd, vd, R, O_.deadBandVoxels * h, &a, LateralMean_, c);
  f.contactPoints = c.points;
  P_ = p;
}

ProxyFrame Proxy::Step(const Eigen::Vector3d& xd, const Eigen::Matrix3d& R, double speedRpm) {
  ProxyFrame f;
  if (!Started_) {
    P_ = Xd_ = xd;
    Fraction_ = 0;
    LateralMean_.setZero();
    Started_ = true;
  }
  if (ForgetMotion_) {
    Xd_ = xd;
    ForgetMotion_ = false;
  }
  const Eigen::Vector3d vd = (xd - Xd_) / T_;
  const Eigen::Vector3d pPrev = P_;
  const double h = Setup_.Bone().Spacing();
  const bool spinning = speedRpm > 0;
  f.devicePositionMm = xd;
  if (O_.rendering == Rendering::Direct) {
    Eigen::Vector3d onTool = Eigen::Vector3d::Zero();
    if (O_.method == ContactMethod::KimPark) {
      const ContactResult c = Contact_->Query(R, xd, 0);
      onTool = c.force;
      f.contactPoints = c.points;
      f.thrustN = c.force.dot(R.col(2));
      if (spinning) {
        int64_t fill = 0;
        f.removedVoxels = Contact_->Cut(R, xd, O_.kimCutDepthVoxels * h, fill);
        f.removedVolumeMm3 = double(fill) / Voxmap::kFull * Setup_.Bone().VoxelVolume();
      }
    } else {
      const ContactResult c = Contact_->Query(R, xd, 0);
      onTool = Coupling_.Stiffness() * c.maxDepthMm * c.normal; // penalty at the device's stiffness
      f.contactPoints = c.points;
      if (spinning) {
        const double adv = -(xd - Xd_).dot(R.col(2));
        FrameInput in;
        in.rotation = R;
        in.position = xd;
        in.motion = xd - Xd_;
        in.feedMmPerRev =
            std::max(adv > 0 ? 60.0 * adv / (speedRpm * T_) : 0.0, Balance_.MinFeed());
        in.speedRpm = speedRpm;
        in.removeMaterial = adv > 0;
        const FrameResult r = Setup_.GetEngine().Step(in);
        f.feedMmPerRev = adv > 0 ? in.feedMmPerRev : 0;
        f.thrustN = r.thrustN;
        f.torqueNmm = r.torqueNmm;
        f.removedVoxels = r.removedVoxels;
        f.removedVolumeMm3 = r.removedVolumeMm3;
        onTool += R * r.forceTool;
        if (r.removedVoxels > 0)
          SyncShell(R, Xd_, xd);
      }
    }
    P_ = xd;
    f.couplingForceN = onTool;
    f.deviceForceN = Coupling_.ToDevice(onTool);
  } else {
    if (O_.method == ContactMethod::Cutting && spinning) {
      CuttingStep(xd, vd, R, speedRpm, f);
    } else {
      ContactResult c;
      P_ = Relax(P_, xd, vd, R, 0.0, nullptr, Eigen::Vector3d::Zero(), c);
      f.contactPoints = c.points;
      f.thrustN = c.force.dot(R.col(2));
      if (O_.method == ContactMethod::KimPark && spinning) {
        int64_t fill = 0;
        f.removedVoxels = Contact_->Cut(R, P_, O_.kimCutDepthVoxels * h, fill);
        f.removedVolumeMm3 = double(fill) / Voxmap::kFull * Setup_.Bone().VoxelVolume();
        f.feedMmPerRev = std::max(0.0, -(P_ - pPrev).dot(R.col(2))) * 60.0 / (speedRpm * T_);
      }
    }
    f.couplingForceN = Coupling_.Force(xd, vd, P_, (P_ - pPrev) / T_);
    f.deviceForceN = Coupling_.DeviceForce(f.couplingForceN);
  }
  f.clamped = f.couplingForceN.norm() > Coupling_.MaxForce();
  f.proxyPositionMm = P_;
  Xd_ = xd;
  return f;
}

} // namespace bm
