#include "bmKimParkContact.h"

#include <cmath>

namespace bm {

KimParkContact::KimParkContact(const ToolDistanceField& sdf, BoneSurfaceShell& shell,
                               double stiffnessPerArea)
    : Sdf_(sdf), Shell_(shell), KA_(stiffnessPerArea) {}

void KimParkContact::ToolBox(const Eigen::Matrix3d& R, const Eigen::Vector3d& p,
                             Eigen::Vector3d& lo, Eigen::Vector3d& hi, ToolPart part) const {
  Eigen::Vector3d tlo, thi;
  Sdf_.PartBox(part, tlo, thi);
  const Eigen::Vector3d c = 0.5 * (tlo + thi), e = 0.5 * (thi - tlo);
  const Eigen::Vector3d wc = R * c + p;
  const Eigen::Vector3d we = R.cwiseAbs() * e;
  lo = wc - we;
  hi = wc + we;
}

ContactResult KimParkContact::Query(const Eigen::Matrix3d& R, const Eigen::Vector3d& p,
                                    double deadBandMm, ToolPart part, double rimBandMm) const {
  ContactResult out;
  Eigen::Vector3d lo, hi;
  ToolBox(R, p, lo, hi, part);
  const double h = Shell_.Bone().Spacing();
  const double kPoint = KA_ * h * h;
  const Eigen::Matrix3d Rt = R.transpose();
  Eigen::Vector3d nsum = Eigen::Vector3d::Zero();
  Shell_.ForEachIn(lo, hi, [&](const SurfacePoint& sp) {
    const Eigen::Vector3d q = Rt * (sp.position - p);
    if (q(0) < Sdf_.Lo()(0) || q(1) < Sdf_.Lo()(1) || q(2) < Sdf_.Lo()(2) || q(0) > Sdf_.Hi()(0) ||
        q(1) > Sdf_.Hi()(1) || q(2) > Sdf_.Hi()(2))
      return;
    Eigen::Vector3d g;
    const double d = Sdf_.Sample(q, g);
    const double pen = -d - deadBandMm;
    if (pen <= 0 || !Sdf_.InPart(q, part, rimBandMm))
      return;
    const double k = kPoint * sp.material;
    out.force += k * pen * sp.normal;
    out.jacobian += k * sp.normal * (R * g).transpose();
    nsum += pen * sp.normal;
    out.maxDepthMm = std::max(out.maxDepthMm, pen);
    ++out.points;
  });
  const double n = nsum.norm();
  if (n > 0)
    out.normal = nsum / n;
  return out;
}

int64_t KimParkContact::Cut(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, double depthMm,
                            int64_t& removedFill) {
  Eigen::Vector3d lo, hi;
  ToolBox(R, p, lo, hi);
  const Eigen::Matrix3d Rt = R.transpose();
  return Shell_.Cut(
      lo, hi,
      [&](const Eigen::Vector3d& x) {
        Eigen::Vector3d g;
        return Sdf_.Sample(Rt * (x - p), g) < -depthMm;
      },
      removedFill);
}

} // namespace bm
