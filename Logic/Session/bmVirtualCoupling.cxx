#include "bmVirtualCoupling.h"

#include <algorithm>
#include <cmath>

namespace bm {

VirtualCoupling::VirtualCoupling(const CouplingOptions& o, const DeviceLimits& limits,
                                 double frameS) {
  K_ = o.stiffnessNPerMm > 0 ? std::min(o.stiffnessNPerMm, limits.maxStiffnessNPerMm)
                             : limits.maxStiffnessNPerMm;
  B_ = o.dampingNsPerMm >= 0 ? o.dampingNsPerMm : K_ * frameS;
  if (limits.maxDampingNsPerMm > 0)
    B_ = std::min(B_, limits.maxDampingNsPerMm);
  MaxForce_ = limits.maxForceN;
}

Eigen::Vector3d VirtualCoupling::Clamp(const Eigen::Vector3d& f, double maxN) {
  if (!f.allFinite() || !(maxN > 0))
    return Eigen::Vector3d::Zero();
  const double n = f.norm();
  if (n <= maxN)
    return f;
  // Scale slightly under the limit so rounding can never put |f| above it.
  return f * (maxN / n * (1.0 - 1e-12));
}

} // namespace bm
