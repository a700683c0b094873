// The default coefficients are what bmForceModel.cxx says they are: re-derived here.
#include <gtest/gtest.h>

#include <cstdio>

#include "bmCalibration.h"
#include "bmForceModel.h"

namespace {

TEST(DefaultCoefficients, LazarGivesTenNewtonsWithKf05AndPositiveElements) {
  bm::TwistDrill drill;
  const bm::ForceModel m = bm::ForceModel::Default(bm::Method::Lazar, drill);
  const auto& c = m.LipCoefficients();
  ASSERT_EQ(c.kc.size(), 2u);
  for (size_t i = 0; i < c.kc.size(); ++i)
    EXPECT_NEAR(c.kt[i] / c.kc[i], 0.5, 1e-9);
  const bm::EdgeIntegral ref = bm::IntegrateEdges(drill, m, 0.02, 1000);
  std::printf("default Lazar at f=0.02, n=1000: thrust %.4f N, torque %.4f N mm\n", ref.thrustN,
              ref.torqueNmm);
  EXPECT_NEAR(ref.thrustN, 10.0, 1e-3);
  EXPECT_NEAR(ref.torqueNmm, 11.354, 2e-3);
  // Every lip element pushes the tool out and resists the spindle, at the four Lee conditions.
  const auto range = drill.EdgeRange(bm::EdgeKind::Lip);
  for (auto [f, n] : bm::LeeConditions())
    for (int i = 0; i <= 400; ++i) {
      const double r = range[0] + (range[1] - range[0]) * (i + 0.5) / 401.0;
      const bm::ElementForce e = m.Evaluate(drill, bm::EdgeKind::Lip, r, f, n);
      EXPECT_GT(e.fz, 0) << "r=" << r << " f=" << f << " n=" << n;
      EXPECT_GT(-e.fy * r, 0) << "r=" << r << " f=" << f << " n=" << n;
    }
}

TEST(DefaultCoefficients, ZhengIsTheLeastSquaresFitToLazarEntryCurves) {
  bm::TwistDrill drill;
  const bm::ForceModel lazar = bm::ForceModel::Default(bm::Method::Lazar, drill);
  const auto data = bm::EntryCurves(drill, lazar, bm::LeeConditions(), 20);
  const bm::ForceModel fit = bm::Calibrate(
      drill, bm::Method::Zheng, {bm::BasisTerm::One, bm::BasisTerm::InvCuttingSpeed}, lazar, data);
  const bm::ForceModel zheng = bm::ForceModel::Default(bm::Method::Zheng, drill);
  const auto& d = zheng.LipCoefficients();
  const auto& f = fit.LipCoefficients();
  std::printf("Zheng fit: kc = %.3f + %.5f/V, kt = %.3f + %.5f/V\n", f.kc[0], f.kc[1], f.kt[0],
              f.kt[1]);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(d.kc[i], f.kc[i], 1e-4 * std::abs(f.kc[i]) + 1e-3);
    EXPECT_NEAR(d.kt[i], f.kt[i], 1e-4 * std::abs(f.kt[i]) + 1e-3);
  }
}

} // namespace
