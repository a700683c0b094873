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
// Force scaling (Docs/Session.md): the tool may push harder than the device can. With force scale
// s, tool force = s x device force: the coupling acts in tool (world) units with K_w = s K and
// B_w = s B, its largest force is s x the device's maximum, and the device is sent -F_vc / s,
// clamped to the device's maximum. The hand feels K and B as without scaling (motion scale 1), and
// the power at the device is the world power / s, so a passive world coupling stays passive at the
// device. s = 1 is unscaled.
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
  /// s: tool force = s x device force (dimensionless, >= 1e-3 and <= kMaxForceScale); default 1.
  double forceScale = 1.0;
};

/// Largest accepted force scale (tool N per device N).
inline constexpr double kMaxForceScale = 1000.0;

/// Throws std::invalid_argument naming the accepted range when s is not a valid force scale.
void CheckForceScale(double s);

class VirtualCoupling {
public:
  VirtualCoupling() = default;
  /// Chooses K and B for a device and a frame period (s). Throws std::invalid_argument on a bad
  /// force scale (CheckForceScale).
  VirtualCoupling(const CouplingOptions& o, const DeviceLimits& limits, double frameS);
  /// World (tool-side) stiffness s K, N/mm.
  double Stiffness() const { return K_; }
  /// World (tool-side) damping s B, N s/mm.
  double Damping() const { return B_; }
  /// Largest tool-side force the coupling renders, s x the device's maximum, N.
  double MaxForce() const { return MaxForce_ * Scale_; }
  /// Largest force the device is ever sent, N.
  double DeviceMaxForce() const { return MaxForce_; }
  /// s, tool N per device N.
  double ForceScale() const { return Scale_; }
  /// Force on the proxy (N) for device and proxy positions (mm) and velocities (mm/s).
  Eigen::Vector3d Force(const Eigen::Vector3d& xd, const Eigen::Vector3d& vd,
                        const Eigen::Vector3d& xp, const Eigen::Vector3d& vp) const {
    return K_ * (xd - xp) + B_ * (vd - vp);
  }
  /// The force for the device, -onProxy / s: finite and at most DeviceMaxForce() in magnitude (N).
  /// Non-finite -> zero.
  Eigen::Vector3d DeviceForce(const Eigen::Vector3d& onProxy) const {
    return Clamp(-onProxy / Scale_, MaxForce_);
  }
  /// A tool-side force (N) as the device force it scales from, onTool / s, clamped like
  /// DeviceForce (direct rendering sends the tool's force itself, not the coupling's reaction).
  Eigen::Vector3d ToDevice(const Eigen::Vector3d& onTool) const {
    return Clamp(onTool / Scale_, MaxForce_);
  }
  /// |f| limited to maxN, direction kept; any NaN or infinite component gives zero.
  static Eigen::Vector3d Clamp(const Eigen::Vector3d& f, double maxN);

private:
  double K_ = 0.4, B_ = 0.0004, MaxForce_ = 3.3, Scale_ = 1.0;
};

} // namespace bm
