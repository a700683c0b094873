// bmAnalyticGlenoid.h - the glenoid phantom's analytic bone in its local frame, without ITK: the
// CT phantom (Logic/IO/bmPhantom.h, which places it in the CT's frame and gives it intensities)
// and the session tests' voxmaps sample the same shape.
//
// Local frame (mm): (u, v) across the face (u along its long axis), w along the outward reaming
// axis, the face centre at the origin; r^2 = u^2 + v^2. The bone is
//   (u/a)^2 + (v/b)^2 <= 1,  -H <= w <= Rc - sqrt(Rc^2 - r^2)
// minus the guide pin's hole r <= rp, w >= -Dp; a cortical shell tc thick (the inner solid has
// semi-axes a - tc, b - tc, face radius Rc + tc and bottom -H + tc) over cancellous bone.
#pragma once

#include <cmath>

namespace bm::glenoid {

constexpr double kA = 20.0;  ///< face half-height a, mm (the face is 40 x 29 mm)
constexpr double kB = 14.5;  ///< face half-width b, mm
constexpr double kRc = 35.0; ///< radius of curvature of the concave face, mm
constexpr double kH = 25.0;  ///< vault depth behind the face centre, mm
constexpr double kRp = 4.0;  ///< guide pin hole radius, mm (1 mm around the reamer's 3 mm nipple)
constexpr double kDp = 10.0; ///< guide pin hole depth, mm
constexpr double kTc = 1.75; ///< cortical shell thickness, mm

enum class Region { Outside, Hole, Cortical, Cancellous };

/// Where local point (u, v, w) (mm) lies; vaultDepthMm: H (default the phantom's 25 mm; a smaller
/// vault keeps a test's voxmap small).
inline Region Classify(double u, double v, double w, double vaultDepthMm = kH) {
  const double r2 = u * u + v * v;
  if ((u / kA) * (u / kA) + (v / kB) * (v / kB) > 1.0 || w < -vaultDepthMm)
    return Region::Outside;
  if (w > kRc - std::sqrt(kRc * kRc - r2))
    return Region::Outside;
  if (r2 <= kRp * kRp && w >= -kDp)
    return Region::Hole;
  const double ai = kA - kTc, bi = kB - kTc, ri = kRc + kTc;
  const bool inner = (u / ai) * (u / ai) + (v / bi) * (v / bi) <= 1.0 && w >= -vaultDepthMm + kTc &&
                     r2 < ri * ri && w <= kRc - std::sqrt(ri * ri - r2);
  return inner ? Region::Cancellous : Region::Cortical;
}

/// Whether local point (u, v, w) (mm) is bone (cortical or cancellous).
inline bool IsBone(double u, double v, double w, double vaultDepthMm = kH) {
  const Region c = Classify(u, v, w, vaultDepthMm);
  return c == Region::Cortical || c == Region::Cancellous;
}

} // namespace bm::glenoid
