#include "bmScapulaPhantom.h"

#include "bmGlenoidGeometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>

namespace bm {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// The scapula's upward rotation with the arm raised above the head, deg (about 60 deg of the
// arm's 180 deg elevation comes from the scapula, Inman's scapulohumeral rhythm; a lung-screening
// scan's raised arms are not at full elevation).
constexpr double kArmRaisedScapulaDeg = 30.0;
// Blade quadrilateral in scapular (x', z'), mm, clockwise: superior angle, neck, neck, inferior
// angle.
constexpr double kBlade[4][2] = {{-100, 40}, {-15, 22}, {-15, -22}, {-85, -115}};
// The spine's base line in scapular (x', z'), mm: from its root on the medial border at z' = 0
// to its lateral end; its width across that line and its height behind the blade's posterior
// face at the root and at the lateral end.
constexpr double kSpineEnd[2] = {-30, 18};
constexpr double kSpineWidthMm = 8, kSpineRootHeightMm = 5, kSpineEndHeightMm = 18;
// The medial border's x' at height z' (the blade's edge from the inferior to the superior angle).
constexpr double MedialBorderX(double z) {
  return kBlade[3][0] +
         (kBlade[0][0] - kBlade[3][0]) * (z - kBlade[3][1]) / (kBlade[0][1] - kBlade[3][1]);
}

void Require(bool ok, const std::string& what) {
  if (!ok)
    throw std::invalid_argument("scapula phantom: " + what);
}

} // namespace

ScapulaPhantomParams ScapulaPhantomParams::B2() {
  ScapulaPhantomParams p;
  p.wearDepthMm = 2.0;
  return p;
}

ScapulaPhantom::ScapulaPhantom(const ScapulaPhantomParams& p) : P_(p) {
  Require(std::abs(p.versionDeg) <= 45, "version must be within [-45, 45] deg");
  Require(std::abs(p.inclinationDeg) <= 45, "inclination must be within [-45, 45] deg");
  Require(p.scapularPlaneDeg >= 0 && p.scapularPlaneDeg <= 80,
          "the scapular plane's angle must be within [0, 80] deg");
  Require(p.corticalMm > 0, "the cortical thickness must be > 0 mm");
  Require(p.glenoidWidthMm > 4 * p.corticalMm && p.glenoidWidthMm <= p.glenoidHeightMm,
          "the glenoid width must exceed 4 cortical thicknesses and not exceed its height");
  Require(p.faceRadiusMm > p.glenoidHeightMm / 2 + 1,
          "the face radius must exceed half the glenoid height by 1 mm");
  Require(p.vaultDepthMm > 2 * p.corticalMm && p.vaultDepthMm <= 60,
          "the vault depth must be within (2 cortical thicknesses, 60] mm");
  Require(p.bladeThicknessMm > 2 * p.corticalMm && p.bladeThicknessMm <= 20,
          "the blade thickness must be within (2 cortical thicknesses, 20] mm");
  Require(p.humeralHeadRadiusMm > 2 * p.corticalMm && p.humeralHeadRadiusMm <= 40,
          "the humeral head radius must be within (2 cortical thicknesses, 40] mm");
  Require(p.jointGapMm >= 1 && p.jointGapMm <= 20, "the joint gap must be within [1, 20] mm");
  Require(p.wearDepthMm >= 0 && p.wearDepthMm <= 10, "the wear depth must be within [0, 10] mm");
  Require(p.wearShiftMm >= 0 && p.wearShiftMm <= 30, "the wear shift must be within [0, 30] mm");
  for (double c : p.glenoidCentreMm)
    Require(std::isfinite(c), "the glenoid centre must be finite");
  for (double r : p.patientRotationDeg)
    Require(std::abs(r) <= 45, "the patient's rotation must be within [-45, 45] deg per axis");

  C_ = p.glenoidCentreMm;
  const double a = p.scapularPlaneDeg * kDeg, sx = p.rightSide ? -1.0 : 1.0;
  Xs_ = {sx * std::cos(a), -std::sin(a), 0};
  As_ = {-sx * std::sin(a), -std::cos(a), 0};
  Zs_ = {0, 0, 1};
  N_ = Normalized(Add(Xs_, Add(Scale(As_, std::tan(p.versionDeg * kDeg)),
                               Scale(Zs_, std::tan(p.inclinationDeg * kDeg)))));
  Ev_ = Normalized(Cross(Zs_, N_));
  if (Dot(Ev_, As_) < 0)
    Ev_ = Scale(Ev_, -1);
  Eu_ = Normalized(AddScaled(Zs_, N_, -Dot(Zs_, N_)));
  // The arm raised: the scapula turned upward (the glenoid toward the head, the inferior angle
  // lateral) about the front-back axis through C, before the patient's rotation.
  if (p.armRaised) {
    const double t = (p.rightSide ? 1.0 : -1.0) * kArmRaisedScapulaDeg * kDeg;
    for (Vec3* v : {&Xs_, &As_, &Zs_, &N_, &Ev_, &Eu_})
      *v = {std::cos(t) * (*v)[0] + std::sin(t) * (*v)[2], (*v)[1],
            -std::sin(t) * (*v)[0] + std::cos(t) * (*v)[2]};
  }
  // The patient's rotation turns every frame vector about C (R = Rz Rx Ry).
  auto turn = [&](Vec3 v) {
    const double r[3] = {p.patientRotationDeg[0] * kDeg, p.patientRotationDeg[1] * kDeg,
                         p.patientRotationDeg[2] * kDeg};
    v = {std::cos(r[1]) * v[0] + std::sin(r[1]) * v[2], v[1],
         -std::sin(r[1]) * v[0] + std::cos(r[1]) * v[2]};
    v = {v[0], std::cos(r[0]) * v[1] - std::sin(r[0]) * v[2],
         std::sin(r[0]) * v[1] + std::cos(r[0]) * v[2]};
    return Vec3{std::cos(r[2]) * v[0] - std::sin(r[2]) * v[1],
                std::sin(r[2]) * v[0] + std::cos(r[2]) * v[1], v[2]};
  };
  for (Vec3* v : {&Xs_, &As_, &Zs_, &N_, &Ev_, &Eu_})
    *v = turn(*v);
  H_ = AddScaled(C_, N_, p.jointGapMm + p.humeralHeadRadiusMm);
  {
    // The shaft: at 135 deg to the head's axis (-n), in the plane of that axis and down (the
    // arm at the side) or up (raised above the head).
    const Vec3 a = Scale(N_, -1.0);
    const Vec3 way = Normalized(AddScaled(Scale(Zs_, p.armRaised ? 1.0 : -1.0), a,
                                          p.armRaised ? -Dot(Zs_, a) : Dot(Zs_, a)));
    const double t = 135.0 * kDeg;
    Shaft_ = Normalized(Add(Scale(a, std::cos(t)), Scale(way, std::sin(t))));
  }
  ComputeTruth();
}

double ScapulaPhantom::FaceHeight(double u, double v) const {
  const double R = P_.faceRadiusMm;
  double f = R - std::sqrt(std::max(0.0, R * R - u * u - v * v));
  if (P_.wearDepthMm > 0) {
    const double r2 = u * u + (v + P_.wearShiftMm) * (v + P_.wearShiftMm);
    if (r2 < R * R)
      f = std::min(f, R - P_.wearDepthMm - std::sqrt(R * R - r2));
  }
  return f;
}

bool ScapulaPhantom::InVault(double u, double v, double w, double s) const {
  const double a = P_.glenoidHeightMm / 2 - s, b = P_.glenoidWidthMm / 2 - s;
  if ((u / a) * (u / a) + (v / b) * (v / b) > 1.0 || w < -P_.vaultDepthMm + s)
    return false;
  const double R = P_.faceRadiusMm, Rs = R + s;
  const double r2 = u * u + v * v;
  if (r2 >= Rs * Rs || w > R - std::sqrt(Rs * Rs - r2))
    return false;
  if (P_.wearDepthMm > 0) {
    const double q2 = u * u + (v + P_.wearShiftMm) * (v + P_.wearShiftMm);
    if (q2 < Rs * Rs && w > R - P_.wearDepthMm - std::sqrt(Rs * Rs - q2))
      return false;
  }
  return true;
}

bool ScapulaPhantom::InBlade(double x, double y, double z, double s) const {
  if (std::abs(y) > P_.bladeThicknessMm / 2 - s)
    return false;
  for (int e = 0; e < 4; ++e) {
    const double* A = kBlade[e];
    const double* B = kBlade[(e + 1) % 4];
    const double ex = B[0] - A[0], ez = B[1] - A[1], len = std::hypot(ex, ez);
    const double d = ((x - A[0]) * ez - (z - A[1]) * ex) / len; // right normal: inside
    if (d < s)
      return false;
  }
  return true;
}

bool ScapulaPhantom::InSpine(double x, double y, double z, double s) const {
  if (!P_.spine)
    return false;
  const double x0 = MedialBorderX(0), ex = kSpineEnd[0] - x0, ez = kSpineEnd[1];
  const double len = std::hypot(ex, ez);
  const double along = ((x - x0) * ex + z * ez) / len, across = ((x - x0) * ez - z * ex) / len;
  if (along > len - s || std::abs(across) > kSpineWidthMm / 2 - s || y > 0)
    return false;
  const double height =
      kSpineRootHeightMm + (kSpineEndHeightMm - kSpineRootHeightMm) * std::max(0.0, along) / len;
  if (y < -(P_.bladeThicknessMm / 2 + height) + s)
    return false;
  // The medial border clips it (the blade's edge from the inferior to the superior angle).
  const double* A = kBlade[3];
  const double* B = kBlade[0];
  const double bx = B[0] - A[0], bz = B[1] - A[1];
  return ((x - A[0]) * bz - (z - A[1]) * bx) / std::hypot(bx, bz) >= s;
}

bool ScapulaPhantom::InHumerus(const Vec3& p, double s) const {
  const double R = P_.humeralHeadRadiusMm;
  const Vec3 d = Sub(p, H_);
  const double along = -Dot(d, N_); // along the head's axis, toward the glenoid
  const double base = -0.24 * R;    // the plane behind the centre that ends the ball
  // The ball on the glenoid's side of the plane.
  if (Norm(d) <= R - s && along >= base + s)
    return true;
  // The neck: along the axis from 3 mm inside the ball's base to 10 mm behind it.
  const double radial = Norm(AddScaled(d, N_, along));
  if (radial <= 0.8 * R - s && along <= base + 3 && along >= base - 10 + s)
    return true;
  // The shaft, from the neck's end.
  const Vec3 start = AddScaled(H_, N_, -(base - 8));
  const Vec3 e = Sub(p, start);
  const double t = Dot(e, Shaft_);
  return t >= 0 && t <= 80 - s && Norm(AddScaled(e, Shaft_, -t)) <= 11 - s;
}

ScapulaPhantom::Tissue ScapulaPhantom::TissueAt(const Vec3& p, Part* part) const {
  const Vec3 d = Sub(p, C_);
  const double u = Dot(d, Eu_), v = Dot(d, Ev_), w = Dot(d, N_);
  const double x = Dot(d, Xs_), y = Dot(d, As_), z = Dot(d, Zs_);
  const double tc = P_.corticalMm;
  if (InVault(u, v, w, 0) || InBlade(x, y, z, 0) || InSpine(x, y, z, 0)) {
    if (part)
      *part = Part::Scapula;
    return InVault(u, v, w, tc) || InBlade(x, y, z, tc) || InSpine(x, y, z, tc) ? Tissue::Cancellous
                                                                                : Tissue::Cortical;
  }
  if (P_.humerus) {
    if (InHumerus(p, 0)) {
      if (part)
        *part = Part::HumeralHead;
      return InHumerus(p, tc) ? Tissue::Cancellous : Tissue::Cortical;
    }
  } else if (const double rh = Distance(p, H_); rh <= P_.humeralHeadRadiusMm) {
    if (part)
      *part = Part::HumeralHead;
    return rh <= P_.humeralHeadRadiusMm - tc ? Tissue::Cancellous : Tissue::Cortical;
  }
  if (part)
    *part = Part::None;
  return Tissue::Soft;
}

float ScapulaPhantom::HU(const Vec3& p) const {
  switch (TissueAt(p)) {
  case Tissue::Cortical:
    return P_.corticalHU;
  case Tissue::Cancellous:
    return P_.cancellousHU;
  case Tissue::Soft:
    break;
  }
  return P_.softHU;
}

void ScapulaPhantom::Bounds(Vec3& lo, Vec3& hi) const {
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  auto grow = [&](const Vec3& q) {
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], q[k]), hi[k] = std::max(hi[k], q[k]);
  };
  const double a = P_.glenoidHeightMm / 2, b = P_.glenoidWidthMm / 2, R = P_.faceRadiusMm;
  const double top = R - std::sqrt(R * R - a * a);
  for (int c = 0; c < 8; ++c) {
    const double u = (c & 1) ? a : -a, v = (c & 2) ? b : -b, w = (c & 4) ? top : -P_.vaultDepthMm;
    grow(AddScaled(AddScaled(AddScaled(C_, Eu_, u), Ev_, v), N_, w));
    const double x = (c & 1) ? -15.0 : -100.0, y = ((c & 2) ? 0.5 : -0.5) * P_.bladeThicknessMm,
                 z = (c & 4) ? 40.0 : -115.0;
    grow(AddScaled(AddScaled(AddScaled(C_, Xs_, x), As_, y), Zs_, z));
    if (P_.spine) { // a box around the spine's plate
      const double sx = (c & 1) ? kSpineEnd[0] + kSpineWidthMm : MedialBorderX(0) - 1,
                   sy = (c & 2) ? 0 : -(P_.bladeThicknessMm / 2 + kSpineEndHeightMm),
                   sz = (c & 4) ? kSpineEnd[1] + kSpineWidthMm : -kSpineWidthMm;
      grow(AddScaled(AddScaled(AddScaled(C_, Xs_, sx), As_, sy), Zs_, sz));
    }
  }
  for (int k = 0; k < 3; ++k) {
    Vec3 e{0, 0, 0};
    e[k] = P_.humeralHeadRadiusMm;
    grow(Add(H_, e));
    grow(Sub(H_, e));
    if (P_.humerus) { // the shaft's far end
      const Vec3 end = AddScaled(AddScaled(H_, N_, 0.24 * P_.humeralHeadRadiusMm + 8), Shaft_, 80);
      e[k] = 11;
      grow(Add(end, e));
      grow(Sub(end, e));
    }
  }
}

void ScapulaPhantom::ComputeTruth() {
  ScapulaTruth& t = Truth_;
  const double a = P_.glenoidHeightMm / 2, b = P_.glenoidWidthMm / 2;
  auto world = [&](double u, double v, double w) {
    return AddScaled(AddScaled(AddScaled(C_, Eu_, u), Ev_, v), N_, w);
  };
  std::vector<Vec3> dense;
  const int nd = 7200;
  dense.reserve(nd);
  for (int i = 0; i < nd; ++i) {
    const double tt = 2 * std::numbers::pi * i / nd, u = a * std::cos(tt), v = b * std::sin(tt);
    dense.push_back(world(u, v, FaceHeight(u, v)));
  }
  // As the detection does: the rim around the current normal, its plane's normal, until the
  // normal settles (the up axis is Z_s projected on the face plane).
  Vec3 n = N_;
  PlaneFit plane;
  for (int it = 0; it < kRimIterations; ++it) {
    const Vec3 eu = Normalized(AddScaled(Zs_, n, -Dot(Zs_, n))), ev = Cross(n, eu);
    t.rim = SupportRim(dense, C_, n, eu, ev, 72, 1e9);
    plane = FitRimPlane(t.rim);
    const Vec3 next = Dot(plane.normal, n) < 0 ? Scale(plane.normal, -1) : plane.normal;
    const bool settled = AngleDeg(next, n) < 1e-3;
    n = next;
    if (settled)
      break;
  }
  t.faceNormal = n;
  // The face's point on the line (rim centroid, normal): bisection on height above the face.
  auto above = [&](double s) {
    const Vec3 d = Sub(AddScaled(plane.centroid, t.faceNormal, s), C_);
    return Dot(d, N_) - FaceHeight(Dot(d, Eu_), Dot(d, Ev_));
  };
  double lo = -40, hi = 40;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (above(mid) > 0 ? hi : lo) = mid;
  }
  t.glenoidCentre = AddScaled(plane.centroid, t.faceNormal, 0.5 * (lo + hi));
  const double zc = Dot(Sub(t.glenoidCentre, C_), Zs_);
  const double xT = MedialBorderX(zc);
  t.trigonum = AddScaled(AddScaled(C_, Xs_, xT), Zs_, zc);
  t.inferiorAngle = AddScaled(AddScaled(C_, Xs_, kBlade[3][0]), Zs_, kBlade[3][1]);
  const ScapularFrame f = MakeScapularFrame(t.glenoidCentre, t.trigonum, t.inferiorAngle);
  t.lateralAxis = f.lateral;
  t.anteriorAxis = f.anterior;
  t.superiorAxis = f.superior;
  t.version3DDeg = Version3DDeg(f, t.faceNormal);
  t.inclinationDeg = InclinationDeg(f, t.faceNormal);
  t.friedmanVersionDeg = FriedmanVersionDeg(dense, t.glenoidCentre, t.trigonum);
  std::tie(t.glenoidHeightMm, t.glenoidWidthMm) =
      RimExtents(t.rim, t.glenoidCentre, t.faceNormal, f.superior);
  t.faceRadiusMm = P_.faceRadiusMm;
  t.humeralHeadCentre = H_;
  t.humeralHeadRadiusMm = P_.humeralHeadRadiusMm;
}

float ScapulaVoxelHU(const ScapulaPhantom& ph, const Vec3& c, const Vec3& sp, int samples) {
  const auto t0 = ph.TissueAt(c);
  bool uniform = true;
  for (int k = 0; k < 8 && uniform; ++k) {
    const Vec3 q{c[0] + ((k & 1) ? 0.5 : -0.5) * sp[0], c[1] + ((k & 2) ? 0.5 : -0.5) * sp[1],
                 c[2] + ((k & 4) ? 0.5 : -0.5) * sp[2]};
    uniform = ph.TissueAt(q) == t0;
  }
  if (uniform || samples <= 1)
    return ph.HU(c);
  double sum = 0;
  for (int k = 0; k < samples; ++k)
    for (int j = 0; j < samples; ++j)
      for (int i = 0; i < samples; ++i)
        sum += ph.HU({c[0] + ((i + 0.5) / samples - 0.5) * sp[0],
                      c[1] + ((j + 0.5) / samples - 0.5) * sp[1],
                      c[2] + ((k + 0.5) / samples - 0.5) * sp[2]});
  return float(sum / (samples * samples * samples));
}

} // namespace bm

#include <nlohmann/json.hpp>

namespace bm {

nlohmann::json ScapulaTruthJson(const ScapulaPhantom& ph) {
  const ScapulaTruth& t = ph.Truth();
  const ScapulaPhantomParams& p = ph.Params();
  nlohmann::json rim = nlohmann::json::array();
  for (const auto& q : t.rim)
    rim.push_back(q);
  return {
      {"phantom", "scapula"},
      {"frame", "world mm, DICOM LPS (x left, y posterior, z superior)"},
      {"parameters",
       {{"version_deg", p.versionDeg},
        {"inclination_deg", p.inclinationDeg},
        {"side", p.rightSide ? "right" : "left"},
        {"patient_rotation_deg", p.patientRotationDeg},
        {"scapular_plane_deg", p.scapularPlaneDeg},
        {"glenoid_height_mm", p.glenoidHeightMm},
        {"glenoid_width_mm", p.glenoidWidthMm},
        {"face_radius_mm", p.faceRadiusMm},
        {"vault_depth_mm", p.vaultDepthMm},
        {"wear_depth_mm", p.wearDepthMm},
        {"wear_shift_mm", p.wearShiftMm},
        {"blade_thickness_mm", p.bladeThicknessMm},
        {"cortical_mm", p.corticalMm},
        {"humeral_head_radius_mm", p.humeralHeadRadiusMm},
        {"joint_gap_mm", p.jointGapMm},
        {"spine", p.spine},
        {"humerus", p.humerus},
        {"arm_raised", p.armRaised},
        {"cortical_hu", p.corticalHU},
        {"cancellous_hu", p.cancellousHU},
        {"soft_hu", p.softHU}}},
      {"glenoid_centre_mm", t.glenoidCentre},
      {"face_normal", t.faceNormal},
      {"trigonum_mm", t.trigonum},
      {"inferior_angle_mm", t.inferiorAngle},
      {"scapular_frame",
       {{"lateral", t.lateralAxis}, {"anterior", t.anteriorAxis}, {"superior", t.superiorAxis}}},
      {"humeral_head_centre_mm", t.humeralHeadCentre},
      {"humeral_head_radius_mm", t.humeralHeadRadiusMm},
      {"version_3d_deg", t.version3DDeg},
      {"inclination_deg", t.inclinationDeg},
      {"friedman_version_deg", t.friedmanVersionDeg},
      {"glenoid_height_mm", t.glenoidHeightMm},
      {"glenoid_width_mm", t.glenoidWidthMm},
      {"face_radius_mm", t.faceRadiusMm},
      {"rim_mm", rim}};
}

} // namespace bm
