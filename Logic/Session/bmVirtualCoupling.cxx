#include "bmVirtualCoupling.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace bm {

void CheckForceScale(double s) {
  if (!(s >= 1e-3 && s <= kMaxForceScale)) {
    std::ostringstream m;
    m << "force scale must be in [0.001, " << kMaxForceScale << "] (tool N per device N), not "
      << s;
    throw std::invalid_argument(m.str());
  }
}

VirtualCoupling::VirtualCoupling(const CouplingOptions& o, const DeviceLimits& limits,
                                 double frameS) {
  CheckForceScale(o.forceScale);
  Scale_ = o.forceScale;
  K_ = o.stiffnessNPerMm > 0 ? std::min(o.stiffnessNPerMm, limits.maxStiffnessNPerMm)
                             : limits.maxStiffnessNPerMm;
  B_ = o.dampingNsPerMm >= 0 ? o.dampingNsPerMm : K_ * frameS;
  if (limits.maxDampingNsPerMm > 0)
    B_ = std::min(B_, limits.maxDampingNsPerMm);
  MaxForce_ = limits.maxForceN;
  // The hand feels K and B; the tool side carries s times the force for the same stretch.
  K_ *= Scale_;
  B_ *= Scale_;
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
