// The reaming outcome (bmReamingOutcome.h) measured on voxmaps built from analytic geometry: a
// glenoid-like bone (an elliptic face 40 x 29 mm, concave with radius 35 mm, a vault 25 mm deep, a
// 1.5 mm cortex over cancellous bone) around a tilted axis, and the same bone after a guide-pin
// hole and the default reamer's face at a set depth. Each figure is checked against the same
// quantity computed from the analytic surfaces on a fine grid.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "bmEdgeQuadrature.h"
#include "bmReamingOutcome.h"

namespace {

constexpr double kA = 20, kB = 14.5, kRc = 35, kH = 25, kTc = 1.5, kRp = 1.6, kDp = 18;
constexpr double kVoxel = 0.4;
const bm::Vec3 kEntry{1.0, -2.0, 0.5};

struct Glenoid {
  bm::Vec3 axis, e1, e2;
  const bm::ArcLipTool reamer;
  double depth;
  double zf;
  explicit Glenoid(double depthMm)
      : axis(bm::Normalized({0.12, -0.05, 1.0})), reamer(), depth(depthMm),
        zf(bm::ForemostCuttingZ(reamer)) {
    const bm::Vec3 ref{1, 0, 0};
    e1 = bm::Normalized(bm::Cross(axis, ref));
    e2 = bm::Cross(axis, e1);
  }
  // Pre-operative face height at (u, v) (concave sphere), mm along the axis.
  static double Face(double r) { return kRc - std::sqrt(kRc * kRc - r * r); }
  double Back(double r) const { return reamer.FaceHeight(r) - zf - depth; }
  static bool InEllipse(double u, double v) {
    return (u / kA) * (u / kA) + (v / kB) * (v / kB) <= 1;
  }
  // 0 void, 1 cancellous, 2 cortical.
  int Tissue(const bm::Vec3& p, bool after) const {
    const bm::Vec3 d = bm::Sub(p, kEntry);
    const double u = bm::Dot(d, e1), v = bm::Dot(d, e2), w = bm::Dot(d, axis);
    const double r = std::hypot(u, v);
    if (!InEllipse(u, v) || w < -kH || r >= kRc || w > Face(r))
      return 0;
    if (after && (r <= kRp && w >= -kDp))
      return 0;
    if (after && r <= reamer.OuterRadius() && w > Back(r))
      return 0;
    return w > Face(r) - kTc || w < -kH + kTc ? 2 : 1;
  }
  bm::Voxmap Make(bool after) const {
    const int n = int(std::ceil(56 / kVoxel));
    bm::Voxmap m({n, n, n}, kVoxel, {kEntry[0] - 28, kEntry[1] - 28, kEntry[2] - 36});
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const auto c = m.GridToWorld({double(i), double(j), double(k)});
          int bone = 0, cortical = 0;
          for (int s = 0; s < 8; ++s) {
            const bm::Vec3 p{c[0] + kVoxel * ((s & 1) - 0.5) / 2,
                             c[1] + kVoxel * (((s >> 1) & 1) - 0.5) / 2,
                             c[2] + kVoxel * (((s >> 2) & 1) - 0.5) / 2};
            const int t = Tissue(p, after);
            bone += t > 0;
            cortical += t == 2;
          }
          if (bone == 0)
            continue;
          const int64_t idx = m.Index(i, j, k);
          m.SetFill(idx, bm::Voxmap::kFull / 8 * bone);
          // Material as the default HU mapping gives it: cortical 1500 HU, cancellous 300 HU.
          m.SetMaterial(idx, Tissue(bm::Vec3{c[0], c[1], c[2]}, false) == 2 || cortical * 2 > bone
                                 ? 1.0f
                                 : 0.25f);
        }
    return m;
  }
};

double FitCentre(const std::vector<std::array<double, 3>>& uvh) {
  Eigen::MatrixXd A(uvh.size(), 6);
  Eigen::VectorXd b(uvh.size());
  for (size_t i = 0; i < uvh.size(); ++i) {
    const auto& [u, v, h] = uvh[i];
    A.row(Eigen::Index(i)) << 1, u, v, u * u, u * v, v * v;
    b(Eigen::Index(i)) = h;
  }
  return A.colPivHouseholderQr().solve(b)(0);
}

struct Case {
  double depthMm;             // reached depth of the reamer's foremost ring
  double baseplateDiameterMm; // 34 mm overhangs the face's 29 mm width: partial seating
};

class ReamingOutcome : public ::testing::TestWithParam<Case> {};

TEST_P(ReamingOutcome, MatchesTheAnalyticGeometry) {
  const Glenoid g(GetParam().depthMm);
  const bm::Voxmap before = g.Make(false), after = g.Make(true);
  bm::ReamingOutcomeOptions o;
  o.baseplateDiameterMm = GetParam().baseplateDiameterMm;
  const double backR = 0.5 * o.baseplateDiameterMm;
  o.pinRadiusMm = kRp;
  o.pinDepthMm = kDp;
  const bm::ReamingOutcome r =
      bm::MeasureReamingOutcome(before, after, kEntry, g.axis, g.reamer, g.depth, o);

  // Analytic figures on a fine polar grid.
  const double holeR = std::max(kRp, g.reamer.Params().nippleRadius) + kVoxel;
  std::vector<std::array<double, 3>> pre, post;
  int total = 0, supported = 0;
  for (double u = -backR; u <= backR; u += 0.1)
    for (double v = -backR; v <= backR; v += 0.1) {
      const double rho = std::hypot(u, v);
      if (rho >= holeR && rho <= 8.0) {
        pre.push_back({u, v, Glenoid::Face(rho)});
        post.push_back({u, v, std::min(Glenoid::Face(rho), g.Back(rho))});
      }
      if (rho > backR || rho < o.pegRadiusMm)
        continue;
      ++total;
      supported += Glenoid::InEllipse(u, v) && Glenoid::Face(rho) >= g.Back(rho) - o.gapMm;
    }
  // The joint line before (the concave face's quadratic at the centre) less the reamed face's
  // height at the centre: the reamer's face seated at the reached depth.
  const double medialisation = FitCentre(pre) - g.Back(0.0);
  const double seating = double(supported) / total;

  EXPECT_LT(r.faceAngleDeg, 2.0) << r.facePoints << " face points";
  EXPECT_NEAR(r.medialisationMm, medialisation, 0.3);
  EXPECT_NEAR(r.seating, seating, 0.05);
  if (backR > kB) {
    EXPECT_LT(seating, 0.95); // the overhang is unsupported
  }
  EXPECT_NEAR(r.boneBeyondPegMm, kH - g.depth - o.pegLengthMm, 2 * kVoxel);
  EXPECT_NEAR(r.boneBeyondPinMm, kH - kDp, 2 * kVoxel);
  EXPECT_NEAR(r.removedMm3, r.removedCorticalMm3 + r.removedCancellousMm3, 1e-6);
  // Removed volume against the voxmaps' own difference is exact by construction; against the
  // geometry it is the partial-volume sampling's error.
  double removed = 0, cortical = 0;
  const double cell = 0.2;
  for (double x = -28; x < 28; x += cell)
    for (double y = -28; y < 28; y += cell)
      for (double z = -36; z < 20; z += cell) {
        const bm::Vec3 p{kEntry[0] + x, kEntry[1] + y, kEntry[2] + z};
        const int t0 = g.Tissue(p, false), t1 = g.Tissue(p, true);
        if (t0 > 0 && t1 == 0) {
          removed += cell * cell * cell;
          cortical += t0 == 2 ? cell * cell * cell : 0;
        }
      }
  EXPECT_NEAR(r.removedMm3, removed, 0.05 * removed);
  EXPECT_NEAR(r.removedCorticalMm3, cortical, 0.1 * cortical + 5);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
}

// The concave face meets the (flatter) reamer at its rim first: at 0.6 mm the rim is reamed and
// the centre barely; a 25 mm baseplate sits on reamed bone. A 34 mm baseplate overhangs the face.
INSTANTIATE_TEST_SUITE_P(Depths, ReamingOutcome,
                         ::testing::Values(Case{0.6, 25.0}, Case{2.5, 25.0}, Case{2.5, 34.0}));

TEST(ReamingOutcomeWarnings, ALongPegPerforatesTheVault) {
  const Glenoid g(2.0);
  const bm::Voxmap before = g.Make(false), after = g.Make(true);
  bm::ReamingOutcomeOptions o;
  o.pinRadiusMm = kRp;
  o.pinDepthMm = 30; // deeper than the 25 mm vault
  o.pegLengthMm = 26;
  const bm::ReamingOutcome r =
      bm::MeasureReamingOutcome(before, after, kEntry, g.axis, g.reamer, g.depth, o);
  EXPECT_NEAR(r.boneBeyondPinMm, kH - 30, 2 * kVoxel);
  EXPECT_NEAR(r.boneBeyondPegMm, kH - 2 - 26, 2 * kVoxel);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("guide pin leaves the glenoid vault"), std::string::npos);
  EXPECT_NE(r.warnings[1].find("perforate the vault"), std::string::npos);
}

TEST(ReamingOutcomeWarnings, RefusesMismatchedGridsAndBadOptions) {
  const Glenoid g(1.0);
  const bm::Voxmap a({10, 10, 10}, 1.0, {0, 0, 0}), b({10, 10, 11}, 1.0, {0, 0, 0});
  EXPECT_THROW(bm::MeasureReamingOutcome(a, b, kEntry, g.axis, g.reamer, 1, {}),
               std::invalid_argument);
  bm::ReamingOutcomeOptions o;
  o.baseplateDiameterMm = 50; // wider than the 36.5 mm reamer whose face shapes the back
  EXPECT_THROW(bm::MeasureReamingOutcome(a, a, kEntry, g.axis, g.reamer, 1, o),
               std::invalid_argument);
  EXPECT_THROW(bm::MeasureReamingOutcome(a, a, kEntry, {0, 0, 2}, g.reamer, 1, {}),
               std::invalid_argument);
}

} // namespace
