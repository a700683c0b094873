// bmVirtualCoupling.h - the spring-damper between the device and the proxy
// (Docs/Interaction.md section 1, Kim et al. eq. 3 with a damper added for passivity).
//
// Force on the proxy: F_vc = K (x_d - x_p) + B (v_d - v_p). The device gets -F_vc, clamped to its
// maximum force; a non-finite force is never sent (it becomes zero). K is at or below the
// device's nominal maximum stiffness. B defaults to K T (T the frame period): twice Colgate's
// bound B > K T / 2 under which the sampled spring cannot generate energy (a zero-order-held
// spring leaks about K dx^2 / 2 per frame, the damper dissipates B dx^2 / T), and stays within the
// device's nominal damping.
//
// Units: mm, mm/s, N, N/mm, N s/mm, s.
#pragma once

#include <Eigen/Core>

#include "bmDevice.h"

namespace bm {

struct CouplingOptions {
  double stiffnessNPerMm =
      0; ///< K; 0 = the device's nominal maximum (default); larger is clamped to it
  double dampingNsPerMm = -1; ///< B; < 0 = K T (default), clamped to the device's nominal damping
};

class VirtualCoupling {
public:
  VirtualCoupling() = default;
  /// Chooses K and B for a device and a frame period (s).
  VirtualCoupling(const CouplingOptions& o, const DeviceLimits& limits, double frameS);
  double Stiffness() const { return K_; }
  double Damping() const { return B_; }
  double MaxForce() const { return MaxForce_; }
  /// Force on the proxy (N) for device and proxy positions (mm) and velocities (mm/s).
  Eigen::Vector3d Force(const Eigen::Vector3d& xd, const Eigen::Vector3d& vd,
                        const Eigen::Vector3d& xp, const Eigen::Vector3d& vp) const {
    return K_ * (xd - xp) + B_ * (vd - vp);
  }
  /// The force for the device: finite and at most MaxForce() in magnitude (N). Non-finite -> zero.
  Eigen::Vector3d DeviceForce(const Eigen::Vector3d& onProxy) const {
    return Clamp(-onProxy, MaxForce_);
  }
  /// |f| limited to maxN, direction kept; any NaN or infinite component gives zero.
  static Eigen::Vector3d Clamp(const Eigen::Vector3d& f, double maxN);

private:
  double K_ = 0.4, B_ = 0.0004, MaxForce_ = 3.3;
};

} // namespace bm
