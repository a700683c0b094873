// bmGlenoidGeometry.h - the geometric definitions the glenoid measurements share: least-squares
// plane and sphere fits (Eigen), the rim by support direction, the scapular frame, 3D version and
// inclination, and Friedman's 2D version. The phantom's truth and the measurement on a CT apply
// the same definitions (Docs/Planning.md, "Measurements"). World mm, LPS; angles in deg.
#pragma once

#include "bmVec3.h"

#include <utility>
#include <vector>

namespace bm {

struct PlaneFit {
  Vec3 centroid{};  ///< mean of the points, mm
  Vec3 normal{};    ///< unit normal (direction of least spread; sign arbitrary)
  double rmsMm = 0; ///< RMS distance of the points from the plane, mm
};
/// Least-squares plane (Eigen's self-adjoint eigen solver on the covariance). Needs >= 3 points;
/// throws std::invalid_argument otherwise.
PlaneFit FitPlane(const std::vector<Vec3>& points);

struct SphereFit {
  Vec3 centre{};
  double radiusMm = 0;
  double rmsMm = 0; ///< RMS of |p - centre| - radius, mm
};
/// Least-squares sphere: the algebraic fit (Eigen's QR) refined by Gauss-Newton on the geometric
/// distances. Needs >= 4 points not on one plane; throws std::invalid_argument otherwise.
SphereFit FitSphere(const std::vector<Vec3>& points);

/// Most rounds of rim -> plane -> normal (SupportRim around the last plane's normal) before the
/// glenoid plane is taken; they stop earlier when the normal moves less than 0.001 deg.
constexpr int kRimIterations = 10;

/// Rim by support direction: for k = 0..count-1, phi = 2 pi k / count, the point of `points`
/// farthest along n + cos(phi) eu + sin(phi) ev from `centre` (the corner where the articular
/// face meets the glenoid's side wall). Only points within maxRadiusMm of the axis (centre, n)
/// count. Returns count points (an empty vector when `points` has none in range).
std::vector<Vec3> SupportRim(const std::vector<Vec3>& points, const Vec3& centre, const Vec3& n,
                             const Vec3& eu, const Vec3& ev, int count = 72,
                             double maxRadiusMm = 40.0);

/// The glenoid plane: the least-squares plane of the closed rim polygon resampled at `samples`
/// points evenly spaced along its perimeter (so the plane does not depend on how densely the
/// support directions sample each part of the rim). Needs >= 3 rim points.
PlaneFit FitRimPlane(const std::vector<Vec3>& rim, int samples = 360);

/// Extents (mm) of points along two directions: {max - min of (p - origin).a1, ... .a2}.
std::pair<double, double> ExtentsAlong(const std::vector<Vec3>& points, const Vec3& origin,
                                       const Vec3& a1, const Vec3& a2);

/// The rim's extents, mm: {height along `up` projected on the plane normal to n (any axis
/// across n when up is parallel to it), width across that}, measured from `centre`.
std::pair<double, double> RimExtents(const std::vector<Vec3>& rim, const Vec3& centre,
                                     const Vec3& n, const Vec3& up);

/// Scapular frame (two-plane method): origin G (glenoid centre); lateral X = (G - T) / |G - T|
/// (T: trigonum); anterior A = the unit normal of the plane through G, T, I (I: inferior angle)
/// turned toward world anterior (-y in LPS); superior Z = X x A turned toward G - I. Throws
/// std::invalid_argument when the three points are (nearly) collinear.
struct ScapularFrame {
  Vec3 origin{}, lateral{}, anterior{}, superior{};
};
ScapularFrame MakeScapularFrame(const Vec3& glenoidCentre, const Vec3& trigonum,
                                const Vec3& inferiorAngle);

/// 3D version of the face normal n: atan2(n.A, n.X), deg (negative = retroversion).
double Version3DDeg(const ScapularFrame& f, const Vec3& n);
/// 3D inclination: atan2(n.Z, n.X), deg (positive = superior).
double InclinationDeg(const ScapularFrame& f, const Vec3& n);
/// The unit direction with the given 3D version and inclination (deg) in the frame:
/// normalize(X + tan(version) A + tan(inclination) Z).
Vec3 DirectionFromAngles(const ScapularFrame& f, double versionDeg, double inclinationDeg);

/// Friedman's 2D version (Friedman et al. 1992) on the axial plane z = centre[2]: the glenoid
/// line joins the points where the closed rim polygon crosses that plane (anterior and
/// posterior), the scapular axis runs from `medialTip` to the glenoid line's midpoint; the
/// version is the angle between the glenoid line and the axis' perpendicular, deg, negative when
/// the glenoid faces posteriorly. anteriorRim/posteriorRim receive the crossings. Throws
/// std::runtime_error when the rim does not cross the plane twice.
double FriedmanVersionDeg(const std::vector<Vec3>& rim, const Vec3& centre, const Vec3& medialTip,
                          Vec3* anteriorRim = nullptr, Vec3* posteriorRim = nullptr);

} // namespace bm
