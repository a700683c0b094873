// bmScapulaPhantom.h - an analytic scapula with a glenoid of set version and inclination and a
// humeral head across the joint: the bone the planning tests measure against (Docs/Planning.md,
// section "Scapula phantom").
//
// Frames (world mm, the CT's DICOM LPS frame: x toward the patient's left, y posterior, z
// superior). The scapular frame has its origin at the glenoid centre C and axes
//   X_s (lateral, along the scapular axis from the trigonum T toward C),
//   A_s (anterior, the scapular plane's normal), Z_s (superior, = world z: the scapula is upright).
// For a right shoulder X_s = (-cos a, -sin a, 0), A_s = (sin a, -cos a, 0) with a = the scapular
// plane's angle to the coronal plane (default 30 deg); a left shoulder is the mirror image in x.
// Scapular coordinates of p: x' = (p - C).X_s, y' = (p - C).A_s, z' = (p - C).Z_s.
//
// Glenoid face normal n = normalize(X_s + tan(version) A_s + tan(inclination) Z_s), so the 3D
// version (the angle of n from X_s in the transverse plane, negative = retroversion) and the
// inclination (its angle from X_s in the scapular plane, positive = superior) are exactly the set
// values. Glenoid axes: e_v = the unit of Z_s x n turned anterior (horizontal, across the face),
// e_u = (Z_s - (Z_s.n) n) normalised (up the face). Local (u, v, w) = ((p-C).e_u, (p-C).e_v,
// (p-C).n). Parts (bone = their union):
//  - glenoid vault: (u/a)^2 + (v/b)^2 <= 1, -H <= w <= f(u, v), where the articular face is
//    f = Rc - sqrt(Rc^2 - u^2 - v^2) (concave, sphere of radius Rc centred at C + Rc n) and, with
//    posterior wear (B2), f = min(that, Rc - d - sqrt(Rc^2 - u^2 - (v + s)^2)): a second sphere of
//    the same radius centred d deeper and s posterior (the neoglenoid); defaults a = 20, b = 14.5
//    (face 40 x 29 mm), Rc = 35, H = 25 mm, no wear;
//  - scapular blade: |y'| <= t/2 (t = 6 mm) over the quadrilateral (x', z') = superior angle
//    (-100, 40), neck (-15, 22), neck (-15, -22), inferior angle (-85, -115);
//  - humeral head: a ball of radius Rh = 22 mm centred at C + (g + Rh) n, g = 4 mm (the joint
//    space at the face centre; it widens toward the rim);
//  - scapular spine (optional, ScapulaPhantomParams::spine): a plate 8 mm wide on the blade's
//    posterior face (y' < 0) along the line from its root T on the medial border at z' = 0 (the
//    trigonum) to (x', z') = (-30, 18) toward the acromion, standing 5 mm behind the blade at its
//    root and 18 mm at its lateral end; the medial border clips it;
//  - proximal humerus (optional, ScapulaPhantomParams::humerus): instead of the whole ball, the
//    head is the ball on the glenoid's side of a plane 0.24 Rh behind its centre (about 60 % of
//    the sphere: the articular cap and the bone around it), on a neck (a cylinder of radius
//    0.8 Rh along the head's axis -n, 10 mm long) and a shaft (radius 11 mm, 80 mm long) at
//    135 deg to the head's axis, downward (the arm at the side).
// Each part has a cortical shell of thickness tc = 1.5 mm (1500 HU) over cancellous bone (300
// HU); soft tissue (40 HU) around. The humeral head is a separate bone (its own component).
#pragma once

#include "bmVec3.h"

#include <vector>

namespace bm {

struct ScapulaPhantomParams {
  double versionDeg = -12.0;          ///< 3D glenoid version, deg (negative = retroversion)
  double inclinationDeg = 8.0;        ///< glenoid inclination, deg (positive = superior tilt)
  bool rightSide = true;              ///< right shoulder (false: the mirror image in x)
  double scapularPlaneDeg = 30.0;     ///< scapular plane's angle to the coronal plane, deg
  Vec3 glenoidCentreMm{-120, 30, 60}; ///< C, world mm
  double glenoidHeightMm = 40.0;      ///< 2a, mm
  double glenoidWidthMm = 29.0;       ///< 2b, mm
  double faceRadiusMm = 35.0;         ///< Rc, radius of curvature of the face, mm
  double vaultDepthMm = 25.0;         ///< H, mm
  double wearDepthMm = 0.0;           ///< d, posterior wear (B2): neoglenoid depth, mm (0 = none)
  double wearShiftMm = 12.0;          ///< s, neoglenoid sphere's posterior offset, mm
  double bladeThicknessMm = 6.0;      ///< t, mm
  double corticalMm = 1.5;            ///< tc, mm
  double humeralHeadRadiusMm = 22.0;  ///< Rh, mm
  double jointGapMm = 4.0;            ///< g, mm
  bool spine = false;                 ///< a scapular spine (above; default none)
  bool humerus = false;               ///< a proximal humerus, not a ball (above; default ball)
  /// The arm raised above the head (with humerus): the shaft points up and the scapula is turned
  /// 30 deg upward (the glenoid toward the head) about the front-back axis through C, before
  /// the patient's rotation. Default: the arm at the side.
  bool armRaised = false;
  /// The patient turned about the glenoid centre: angles about world x, y, z (deg, each within
  /// +-45), applied y, then x, then z (VTK's order, as BM CT Bone's box). The truth turns with it;
  /// the 3D version and inclination, measured in the scapula's own frame, do not change.
  Vec3 patientRotationDeg{0, 0, 0};
  float corticalHU = 1500, cancellousHU = 300, softHU = 40;

  /// A Walch B2 glenoid: the defaults with 2 mm posterior wear (the posterior rim 5 mm lower).
  static ScapulaPhantomParams B2();
};

/// The phantom's analytic truth, world mm and unit vectors; angles in deg. The glenoid plane,
/// rim, centre, height and width follow the definitions of Docs/Planning.md applied to the
/// analytic surface (rim points by support direction, least-squares plane), so they are what a
/// perfect measurement gives; without wear they are exactly C, n, 2a and 2b.
struct ScapulaTruth {
  Vec3 glenoidCentre{}; ///< the face's point on the rim plane's normal through the rim centroid
  Vec3 faceNormal{};    ///< rim plane normal, lateral (out of the joint)
  Vec3 trigonum{};      ///< T: the medial border at the glenoid centre's height (z' = 0)
  Vec3 inferiorAngle{}; ///< I, the blade's inferior vertex
  Vec3 lateralAxis{}, anteriorAxis{}, superiorAxis{}; ///< X_s, A_s, Z_s
  Vec3 humeralHeadCentre{};
  double humeralHeadRadiusMm = 0;
  double version3DDeg = 0;       ///< of faceNormal against the scapular frame
  double inclinationDeg = 0;     ///< of faceNormal against the scapular frame
  double friedmanVersionDeg = 0; ///< Friedman 2D on the axial plane through the centre
  double glenoidHeightMm = 0, glenoidWidthMm = 0;
  double faceRadiusMm = 0; ///< Rc (of the native face)
  std::vector<Vec3> rim;   ///< rim points (72, by support direction), world mm
};

class ScapulaPhantom {
public:
  enum class Tissue { Soft, Cortical, Cancellous };
  enum class Part { None, Scapula, HumeralHead };

  /// Throws std::invalid_argument naming a parameter out of range.
  explicit ScapulaPhantom(const ScapulaPhantomParams& p = {});
  const ScapulaPhantomParams& Params() const { return P_; }

  /// Tissue and part at world point p (mm).
  Tissue TissueAt(const Vec3& p, Part* part = nullptr) const;
  /// HU at p without partial volume or noise.
  float HU(const Vec3& p) const;
  /// Axis-aligned world box (mm) holding all bone.
  void Bounds(Vec3& lo, Vec3& hi) const;
  /// The analytic truth (computed once, at construction).
  const ScapulaTruth& Truth() const { return Truth_; }
  /// Height of the articular face above C along n at glenoid coordinates (u, v), mm.
  double FaceHeight(double u, double v) const;
  /// Glenoid frame: e_u, e_v, n (world unit vectors).
  const Vec3& Eu() const { return Eu_; }
  const Vec3& Ev() const { return Ev_; }
  const Vec3& N() const { return N_; }

private:
  bool InVault(double u, double v, double w, double shrink) const;
  bool InBlade(double x, double y, double z, double shrink) const;
  bool InSpine(double x, double y, double z, double shrink) const;
  bool InHumerus(const Vec3& p, double shrink) const;
  void ComputeTruth();

  ScapulaPhantomParams P_;
  Vec3 C_{}, Xs_{}, As_{}, Zs_{}, N_{}, Eu_{}, Ev_{}, H_{};
  Vec3 Shaft_{}; ///< the humeral shaft's direction from the neck (with humerus)
  ScapulaTruth Truth_;
};

/// Mean of `samples`^3 sub-samples of the phantom's HU over the voxel of edge `spacing` (mm) at
/// world centre c (partial volume); the sub-samples are taken only where the voxel's corners
/// differ in tissue (elsewhere the centre's HU).
float ScapulaVoxelHU(const ScapulaPhantom& ph, const Vec3& c, const Vec3& spacing, int samples);

} // namespace bm

#include <nlohmann/json_fwd.hpp>

namespace bm {
/// The truth and the parameters as JSON (keys in snake_case with units: "glenoid_centre_mm",
/// "face_normal", "version_3d_deg", ...), for `bmsim phantom scapula` and reports.
nlohmann::json ScapulaTruthJson(const ScapulaPhantom& phantom);
} // namespace bm
