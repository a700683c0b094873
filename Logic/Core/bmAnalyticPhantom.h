// bmAnalyticPhantom.h - the built-in phantoms' analytic bone, without ITK: their geometry, volume
// and tissue at any point. The CT phantoms (Logic/IO/bmPhantom.h) give each tissue its HU and
// write the CT; tests and benchmarks sample the same shapes straight into voxmaps.
//
// Glenoid phantom ("glenoid"), world mm in the CT's LPS frame, a right shoulder:
//   face centre C = (-60, 20, 40) mm, outward reaming axis n = (-1, 0, 0) (lateral), the face's
//   long (superior-inferior) axis e_u = (0, 0, 1), its short (anterior-posterior) axis e_v = (0, 1,
//   0). In local coordinates (u, v, w) = ((p-C).e_u, (p-C).e_v, (p-C).n) and r^2 = u^2 + v^2 the
//   bone is
//     (u/a)^2 + (v/b)^2 <= 1,  -H <= w <= s(r) = Rc - sqrt(Rc^2 - r^2)
//   minus the pilot (guide pin) hole r <= rp, w >= -Dp:
//   a = 20 mm, b = 14.5 mm (face 40 x 29 mm), Rc = 35 mm (concave face, radius of curvature),
//   H = 25 mm (vault depth behind the face centre), rp = 4.0 mm, Dp = 10 mm. The pilot hole
//   leaves the reamer's 3 mm guide nipple 1 mm of clearance, about two CT voxels: the voxmap's
//   partial-volume wall spreads over one CT voxel, and a rigid nipple must not graze it.
//   Cortical shell tc = 1.75 mm (the inner solid has semi-axes a - tc, b - tc, the face sphere
//   radius Rc + tc and its bottom at -H + tc) at 1500 HU over cancellous bone at 300 HU; the pilot
//   hole holds fluid (0 HU); soft tissue (40 HU) around.
//   Analytic bone volume: V = pi a b (H + Rc) - (1/3) int_0^2pi [Rc^3 - (Rc^2 - rho(t)^2)^1.5] dt
//   - [pi rp^2 (Dp + Rc) - (2 pi / 3)(Rc^3 - (Rc^2 - rp^2)^1.5)], rho(t) = the ellipse's radius at
//   angle t (a periodic integral, evaluated to ~1e-12 by the trapezoid rule).
// Block phantom ("block"): a cortical bone block (1600 HU) in air (-1000 HU),
//   x, y in [-3, 3] mm, z in [-4, 0] mm: top face at z = 0, centre C = (0, 0, 0), outward axis
//   n = (0, 0, 1) (drilled along -z). Volume 144 mm^3.
//
// Shoulder phantom ("shoulder"): two bones across a joint space, for the separation of touching
//   bones. A humeral head, a sphere of radius 22 mm centred at (0, 0, 0) (volume 44 602 mm^3),
//   and a scapula-like glenoid plate x in [-41.5, -25.5], y in [-20, 20], z in [-30, 30] mm
//   (volume 38 400 mm^3), 3.5 mm apart at x = -22 .. -25.5; each a 1.5 mm cortical shell
//   (1500 HU) over cancellous bone (head 250 HU, plate 300 HU) in soft tissue (40 HU). Centre =
//   the plate's face centre (-25.5, 0, 0), outward axis (1, 0, 0). Its CT is blurred by the
//   scanner's point spread (Gaussian, sigma 1.5 mm by default), which joins the two bones across
//   the joint space at the bone threshold, as in a patient's shoulder CT.
//
//
// Units: world mm.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "bmVoxmap.h"

namespace bm {

struct PhantomInfo {
  std::string name;                 ///< "glenoid", "block" or "shoulder"
  std::array<double, 3> centreMm{}; ///< glenoid / plate face centre, block top-face centre, mm
  std::array<double, 3>
      axisOut{};                ///< outward unit axis at the centre (the tool feeds along -axisOut)
  double boneVolumeMm3 = 0;     ///< analytic bone volume, mm^3
  Box3 boneBounds;              ///< analytic world box of the bone, mm
  double pilotHoleRadiusMm = 0; ///< glenoid: guide pin hole radius (0 for the block)
  double pilotHoleDepthMm = 0;  ///< glenoid: depth below the face centre
};

/// What a phantom holds at a point.
enum class PhantomTissue {
  Outside,       ///< soft tissue (glenoid, shoulder) or air (block)
  Fluid,         ///< the glenoid's pilot hole
  Cortical,      ///< cortical bone (the block is all cortical)
  Cancellous,    ///< cancellous bone (the glenoid's, the shoulder's plate)
  HeadCancellous ///< the shoulder's humeral head, less dense than the plate
};

/// Names of the built-in phantoms.
std::vector<std::string> PhantomNames();
/// Geometry and analytic volume; throws std::invalid_argument on an unknown name.
PhantomInfo GetPhantomInfo(const std::string& name);
/// The tissue at world point p (mm); throws std::invalid_argument on an unknown name.
PhantomTissue PhantomTissueAt(const std::string& name, const std::array<double, 3>& p);
/// True when world point p (mm) is bone.
bool PhantomIsBone(const std::string& name, const std::array<double, 3>& p);

} // namespace bm
