#include "bmReamingOutcome.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "bmEdgeQuadrature.h"

namespace bm {
namespace {

constexpr double kTopMm = 20.0;   // rays start this far above the entry, mm
constexpr double kReachMm = 80.0; // and end this far below it, mm

struct Frame {
  Vec3 entry, axis, e1, e2;
  Vec3 At(double u, double v, double t) const {
    return AddScaled(AddScaled(AddScaled(entry, e1, u), e2, v), axis, t);
  }
};

double FractionAt(const Voxmap& m, const Vec3& p) {
  std::array<int, 3> ijk{};
  return m.VoxelAt(p, ijk) ? m.Fraction(m.Index(ijk[0], ijk[1], ijk[2])) : 0.0;
}

// Height (along the axis from the entry, mm) of the first voxel at least half full met coming
// down the ray at (u, v); nothing when the ray meets no bone.
std::optional<double> SurfaceHeight(const Voxmap& m, const Frame& f, double u, double v) {
  const double step = 0.25 * m.Spacing();
  for (double t = kTopMm; t >= -kReachMm; t -= step)
    if (FractionAt(m, f.At(u, v, t)) >= 0.5)
      return t;
  return std::nullopt;
}

// Depth below the entry (mm) where the ray at (u, v), having entered bone, meets the first void
// run of at least 1 mm (the far cortex ends); kReachMm when it never does.
double ExitDepth(const Voxmap& m, const Frame& f, double u, double v) {
  const double step = 0.25 * m.Spacing();
  bool entered = false;
  double voidStart = 0;
  bool inVoid = false;
  for (double t = kTopMm; t >= -kReachMm; t -= step) {
    const bool bone = FractionAt(m, f.At(u, v, t)) >= 0.5;
    if (!entered) {
      entered = bone;
      continue;
    }
    if (bone) {
      inVoid = false;
    } else if (!inVoid) {
      inVoid = true;
      voidStart = t;
    } else if (voidStart - t >= 1.0) {
      return -voidStart;
    }
  }
  return kReachMm;
}

// Least-squares h = a + b u + c v + d u^2 + e uv + g v^2; returns a (the height at the centre).
double QuadraticCentre(const std::vector<std::array<double, 3>>& uvh) {
  Eigen::MatrixXd A(uvh.size(), 6);
  Eigen::VectorXd b(uvh.size());
  for (size_t i = 0; i < uvh.size(); ++i) {
    const auto& [u, v, h] = uvh[i];
    A.row(Eigen::Index(i)) << 1, u, v, u * u, u * v, v * v;
    b(Eigen::Index(i)) = h;
  }
  return A.colPivHouseholderQr().solve(b)(0);
}

} // namespace

ReamingOutcome MeasureReamingOutcome(const Voxmap& before, const Voxmap& after, const Vec3& entry,
                                     const Vec3& axisIn, const ToolModel& reamer,
                                     double reachedDepthMm, const ReamingOutcomeOptions& o) {
  if (before.Dims() != after.Dims() || before.Spacing() != after.Spacing() ||
      before.Origin() != after.Origin())
    throw std::invalid_argument("reaming outcome: the voxmaps before and after differ in grid");
  if (!(std::abs(Norm(axisIn) - 1.0) < 1e-3))
    throw std::invalid_argument("reaming outcome: the axis must be a unit vector");
  if (!(o.baseplateDiameterMm > 0 && o.gapMm > 0 && o.pegLengthMm > 0 && o.pegRadiusMm > 0 &&
        o.pinRadiusMm > 0 && o.pinDepthMm >= 0 && o.backRadiusMm >= 0 &&
        2 * o.pegRadiusMm < o.baseplateDiameterMm))
    throw std::invalid_argument(
        "reaming outcome: baseplate diameter, gap, peg length and radius and pin radius must be "
        "> 0 (pin depth and back radius >= 0) and the peg narrower than the baseplate");
  const auto* arc = dynamic_cast<const ArcLipTool*>(&reamer);
  const double backR = 0.5 * o.baseplateDiameterMm;
  if (o.backRadiusMm == 0 && (!arc || backR > reamer.OuterRadius()))
    throw std::invalid_argument(
        "reaming outcome: a back shaped as the reamer's face needs a reamer at least as wide as "
        "the baseplate (" +
        std::to_string(o.baseplateDiameterMm) + " mm)");
  if (o.backRadiusMm > 0 && o.backRadiusMm < backR)
    throw std::invalid_argument("reaming outcome: the back radius must be at least half the "
                                "baseplate diameter");

  Frame f;
  f.entry = entry;
  f.axis = Normalized(axisIn);
  const Vec3 ref = std::abs(f.axis[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  f.e1 = Normalized(Cross(f.axis, ref));
  f.e2 = Cross(f.axis, f.e1);
  const double h = before.Spacing();
  const double d = reachedDepthMm;

  ReamingOutcome out;
  out.reachedDepthMm = d;

  // Removed volume by tissue.
  const auto& n = before.Dims();
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const int64_t idx = before.Index(i, j, k);
        const double removed = (before.Fraction(idx) - after.Fraction(idx)) * before.VoxelVolume();
        if (removed <= 0)
          continue;
        out.removedMm3 += removed;
        (before.Material(idx) >= kCorticalMaterial ? out.removedCorticalMm3
                                                   : out.removedCancellousMm3) += removed;
      }

  // The reamed face and the joint line.
  const double holeR = std::max(o.pinRadiusMm, arc ? arc->Params().nippleRadius : 0.0) + h;
  const double faceR = 0.9 * reamer.OuterRadius();
  // Rays on a grid symmetric about the axis; the plane is fitted to the cut points whose mirror
  // point (-u, -v) was cut too, so that a face of revolution reamed off-centre (the reamer meets
  // one side of a retroverted glenoid first) does not tilt the fit.
  const int nGrid = int(std::floor(faceR / h));
  const int side = 2 * nGrid + 1;
  std::vector<std::optional<Eigen::Vector3d>> cutAt(size_t(side) * size_t(side));
  std::vector<std::array<double, 3>> preCentre, postCentre;
  // The reamed surface brought to the centre along the reamer's own face (arc reamers): a cut
  // point at rho, height ha, puts the reamed face's centre at ha - (F(rho) - F(0)).
  std::vector<double> reamedCentre;
  for (int iu = -nGrid; iu <= nGrid; ++iu)
    for (int iv = -nGrid; iv <= nGrid; ++iv) {
      const double u = iu * h, v = iv * h;
      const double rho = std::hypot(u, v);
      if (rho > faceR || rho < holeR)
        continue;
      const auto hb = SurfaceHeight(before, f, u, v);
      const auto ha = SurfaceHeight(after, f, u, v);
      if (rho <= 8.0) {
        if (hb)
          preCentre.push_back({u, v, *hb});
        if (ha)
          postCentre.push_back({u, v, *ha});
      }
      if (hb && ha && *hb - *ha > h && arc && rho <= 8.0)
        reamedCentre.push_back(*ha - (arc->FaceHeight(rho) - arc->FaceHeight(0)));
      if (hb && ha && *hb - *ha > h) {
        const Vec3 p = f.At(u, v, *ha);
        cutAt[size_t(iu + nGrid) * side + size_t(iv + nGrid)] = Eigen::Vector3d(p[0], p[1], p[2]);
      }
    }
  std::vector<Eigen::Vector3d> cut;
  for (int iu = -nGrid; iu <= nGrid; ++iu)
    for (int iv = -nGrid; iv <= nGrid; ++iv) {
      const auto& a = cutAt[size_t(iu + nGrid) * side + size_t(iv + nGrid)];
      const auto& b = cutAt[size_t(nGrid - iu) * side + size_t(nGrid - iv)];
      if (a && b)
        cut.push_back(*a);
    }
  out.facePoints = int(cut.size());
  if (cut.size() >= 10) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : cut)
      c += p;
    c /= double(cut.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& p : cut)
      cov += (p - c) * (p - c).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    Eigen::Vector3d nrm = es.eigenvectors().col(0);
    if (nrm.dot(Eigen::Vector3d(f.axis[0], f.axis[1], f.axis[2])) < 0)
      nrm = -nrm;
    out.faceNormal = {nrm(0), nrm(1), nrm(2)};
    out.faceAngleDeg = AngleDeg(out.faceNormal, f.axis);
    // Where the axis crosses the fitted plane, below the entry.
    const Eigen::Vector3d e(f.entry[0], f.entry[1], f.entry[2]);
    const Eigen::Vector3d ax(f.axis[0], f.axis[1], f.axis[2]);
    out.faceDepthMm = -(c - e).dot(nrm) / ax.dot(nrm);
  } else {
    out.warnings.push_back("the reamer cut too little of the face to fit its plane (" +
                           std::to_string(cut.size()) + " points)");
  }
  // Medialisation: the pre-operative face (a smooth concave surface) by its quadratic; the reamed
  // face by the reamer's profile when the reamer cut within 8 mm of the axis (a quadratic over the
  // annulus outside the pin's hole extrapolates the reamer's ring-shaped face badly: 2.2 mm at
  // 0.87 mm voxels, 0.8 mm at 0.22 mm on the same cut), else by its quadratic too.
  if (preCentre.size() >= 12 && reamedCentre.size() >= 12) {
    double sum = 0;
    for (double c : reamedCentre)
      sum += c;
    out.medialisationMm = QuadraticCentre(preCentre) - sum / double(reamedCentre.size());
  } else if (preCentre.size() >= 12 && postCentre.size() >= 12) {
    out.medialisationMm = QuadraticCentre(preCentre) - QuadraticCentre(postCentre);
  }

  // Backside seating.
  const double zf = ForemostCuttingZ(reamer);
  const double w = arc ? arc->Params().arcCentreOffset : 0.0;
  const double rb = o.backRadiusMm;
  const double cTop = -d + rb - std::sqrt(std::max(0.0, rb * rb - w * w));
  auto backHeight = [&](double rho) {
    if (rb == 0)
      return arc->FaceHeight(rho) - zf - d;
    return cTop - (rb - std::sqrt(rb * rb - rho * rho));
  };
  const double ds = 0.5 * h;
  int total = 0, supported = 0;
  for (double u = -backR; u <= backR; u += ds)
    for (double v = -backR; v <= backR; v += ds) {
      const double rho = std::hypot(u, v);
      if (rho > backR || rho < o.pegRadiusMm)
        continue;
      ++total;
      const auto ha = SurfaceHeight(after, f, u, v);
      if (ha && *ha >= backHeight(rho) - o.gapMm)
        ++supported;
    }
  out.seating = total > 0 ? double(supported) / total : 0.0;

  // Bone beyond the pin's and the peg's tips, along the axis through the pre-operative vault.
  const double pinExit = ExitDepth(before, f, 0, 0);
  double pegExit = pinExit;
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * 3.14159265358979323846 * k / 8;
    pegExit = std::min(
        pegExit, ExitDepth(before, f, o.pegRadiusMm * std::cos(a), o.pegRadiusMm * std::sin(a)));
  }
  out.boneBeyondPinMm = o.pinDepthMm > 0 ? pinExit - o.pinDepthMm : pinExit;
  out.boneBeyondPegMm = pegExit - (d + o.pegLengthMm);
  std::ostringstream msg;
  msg.precision(3);
  if (o.pinDepthMm > 0 && out.boneBeyondPinMm < 0) {
    msg << "the guide pin leaves the glenoid vault: its tip is " << -out.boneBeyondPinMm
        << " mm beyond the far cortex";
    out.warnings.push_back(msg.str());
    msg.str("");
  }
  if (out.boneBeyondPegMm < 0) {
    msg << "a " << o.pegLengthMm << " mm central peg would perforate the vault by "
        << -out.boneBeyondPegMm << " mm";
    out.warnings.push_back(msg.str());
  }
  return out;
}

nlohmann::json ReamingOutcome::ToJson() const {
  return {{"reached_depth_mm", reachedDepthMm},
          {"removed_volume_mm3", removedMm3},
          {"removed_cortical_mm3", removedCorticalMm3},
          {"removed_cancellous_mm3", removedCancellousMm3},
          {"reamed_face_normal", faceNormal},
          {"reamed_face_angle_to_axis_deg", faceAngleDeg},
          {"reamed_face_points", facePoints},
          {"face_depth_mm", faceDepthMm},
          {"medialisation_mm", medialisationMm},
          {"seating_fraction", seating},
          {"bone_beyond_pin_mm", boneBeyondPinMm},
          {"bone_beyond_peg_mm", boneBeyondPegMm},
          {"warnings", warnings}};
}

} // namespace bm
