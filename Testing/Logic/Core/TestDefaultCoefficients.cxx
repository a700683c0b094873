// The default coefficients are what bmForceModel.cxx says they are: the default drilling set is
// the fit to the shipped published data (Docs/Calibration.md), re-derived here, and the assumed
// set the paper's reproductions name keeps its values.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "bmCalibration.h"
#include "bmCalibrationData.h"
#include "bmEdgeQuadrature.h"
#include "bmForceModel.h"

namespace {

TEST(DefaultCoefficients, AssumedSetGivesTenNewtonsWithKf05AndPositiveElements) {
  bm::TwistDrill drill;
  const bm::ForceModel m = bm::ForceModel::Assumed(bm::Method::Lazar, drill);
  EXPECT_EQ(m.Provenance().name, "faieghi-assumed");
  EXPECT_FALSE(m.Provenance().calibrated);
  const auto& c = m.LipCoefficients();
  ASSERT_EQ(c.kc.size(), 2u);
  for (size_t i = 0; i < c.kc.size(); ++i)
    EXPECT_NEAR(c.kt[i] / c.kc[i], 0.5, 1e-9);
  const bm::EdgeIntegral ref = bm::IntegrateEdges(drill, m, 0.02, 1000);
  std::printf("assumed Lazar at f=0.02, n=1000: thrust %.4f N, torque %.4f N mm\n", ref.thrustN,
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
  // The named file holds the same set (the paper's reproduction names it explicitly).
  const bm::ForceModel named =
      bm::ForceModel::FromJson({{"coefficients", "faieghi-assumed"}}, drill);
  EXPECT_EQ(named.LipCoefficients().kc, c.kc);
  EXPECT_EQ(named.LipCoefficients().kt, c.kt);
  EXPECT_EQ(named.ChiselCoefficients().kc, m.ChiselCoefficients().kc);
  EXPECT_EQ(named.Provenance().name, "faieghi-assumed");
}

TEST(DefaultCoefficients, ZhengIsTheLeastSquaresFitToAssumedLazarEntryCurves) {
  bm::TwistDrill drill;
  const bm::ForceModel lazar = bm::ForceModel::Assumed(bm::Method::Lazar, drill);
  const auto data = bm::EntryCurves(drill, lazar, bm::LeeConditions(), 20);
  const bm::ForceModel fit = bm::Calibrate(
      drill, bm::Method::Zheng, {bm::BasisTerm::One, bm::BasisTerm::InvCuttingSpeed}, lazar, data);
  const bm::ForceModel zheng = bm::ForceModel::Default(bm::Method::Zheng, drill);
  EXPECT_EQ(zheng.Provenance().name, "zheng-fit-to-faieghi-assumed");
  EXPECT_EQ(zheng.LipCoefficients().kc,
            bm::ForceModel::Assumed(bm::Method::Zheng, drill).LipCoefficients().kc);
  const auto& d = zheng.LipCoefficients();
  const auto& f = fit.LipCoefficients();
  std::printf("Zheng fit: kc = %.3f + %.5f/V, kt = %.3f + %.5f/V\n", f.kc[0], f.kc[1], f.kt[0],
              f.kt[1]);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(d.kc[i], f.kc[i], 1e-4 * std::abs(f.kc[i]) + 1e-3);
    EXPECT_NEAR(d.kt[i], f.kt[i], 1e-4 * std::abs(f.kt[i]) + 1e-3);
  }
  EXPECT_FALSE(zheng.Provenance().calibrated);
}

// ------------------------------------------------------------------------------------------------
// The default drilling set "drilling-bovine-orelaja2020" (Resources/Calibration): the fit of
// k = b 1000/n, shared by every edge, to the bovine rows of drilling-published.csv.

const std::filesystem::path kData =
    std::filesystem::path(BM_SOURCE_DIR) / "Resources/Calibration/drilling-published.csv";

std::vector<bm::CalibrationSample> BovineRows() {
  std::vector<bm::CalibrationSample> out;
  for (const auto& r : bm::ReadCalibrationCsv(kData))
    if (r.sample.bone == "bovine femur")
      out.push_back(r.sample);
  return out;
}

bm::ForceModel Bovine(const bm::ToolModel& tool) {
  return bm::ForceModel::FromJson({{"coefficients", "drilling-bovine-orelaja2020"}}, tool);
}

TEST(DefaultCoefficients, BovineSetIsTheFitToThePublishedBovineRows) {
  const bm::TwistDrill drill;
  const bm::ForceModel set = Bovine(drill);
  EXPECT_EQ(set.Provenance().name, "drilling-bovine-orelaja2020");
  EXPECT_TRUE(set.Provenance().calibrated);
  const auto rows = BovineRows();
  ASSERT_EQ(rows.size(), 2u);
  bm::CalibrationOptions shared;
  shared.chiselSharesLipCoefficients = true;
  const bm::CalibrationFit fit = bm::CalibrateFit(
      drill, bm::Method::Lazar, {bm::BasisTerm::InvSpindleSpeed}, set, rows, shared);
  for (const auto* c : {&set.LipCoefficients(), &set.ChiselCoefficients()}) {
    ASSERT_EQ(c->kc.size(), 1u);
    EXPECT_NEAR(c->kc[0], fit.model.LipCoefficients().kc[0], 1e-9 * c->kc[0]);
    EXPECT_NEAR(c->kt[0], fit.model.LipCoefficients().kt[0], 1e-9 * c->kt[0]);
  }
  // The published rows are reproduced within 10 % (two numbers fit four).
  for (const auto& s : rows) {
    const bm::EdgeIntegral p = bm::Predict(drill, set, s);
    std::printf("bovine n %4.0f: thrust %.2f N (measured %.2f), torque %.2f N mm (measured %.2f), "
                "ratio %.3f mm\n",
                s.speedRpm, p.thrustN, s.thrustN, p.torqueNmm, s.torqueNmm,
                p.torqueNmm / p.thrustN);
    EXPECT_NEAR(p.thrustN, s.thrustN, 0.1 * s.thrustN);
    EXPECT_NEAR(p.torqueNmm, s.torqueNmm, 0.1 * s.torqueNmm);
    // Published 2.5 mm bovine drilling: 1.96-2.05 mm.
    EXPECT_GE(p.torqueNmm / p.thrustN, 1.9);
    EXPECT_LE(p.torqueNmm / p.thrustN, 2.05);
  }
}

TEST(DefaultCoefficients, DefaultDrillingSetFallsWithSpeedAtThePublishedRatio) {
  const bm::TwistDrill drill; // the reference 2.5 mm drill
  const bm::ForceModel set = bm::ForceModel::Default(bm::Method::Lazar, drill);
  EXPECT_EQ(set.Provenance().name, "drilling-bovine-orelaja2020");
  EXPECT_TRUE(set.Provenance().calibrated);
  EXPECT_EQ(set.LipCoefficients().kc, Bovine(drill).LipCoefficients().kc);
  EXPECT_EQ(set.ChiselCoefficients().kt, Bovine(drill).ChiselCoefficients().kt);
  const bm::EdgeIntegral at1000 = bm::IntegrateEdges(drill, set, 0.02, 1000);
  const bm::EdgeIntegral at1500 = bm::IntegrateEdges(drill, set, 0.02, 1500);
  std::printf("default set at f=0.02: 1000 rpm %.4f N, %.4f N mm (ratio %.3f mm); 1500 rpm %.4f N, "
              "%.4f N mm (thrust %.1f %% lower)\n",
              at1000.thrustN, at1000.torqueNmm, at1000.torqueNmm / at1000.thrustN, at1500.thrustN,
              at1500.torqueNmm, 100 * (1 - at1500.thrustN / at1000.thrustN));
  EXPECT_NEAR(at1000.thrustN, 7.774, 0.005);
  EXPECT_NEAR(at1000.torqueNmm, 15.979, 0.005);
  EXPECT_NEAR(at1500.thrustN / at1000.thrustN, 2.0 / 3.0, 1e-9); // k proportional to 1 / n
  EXPECT_NEAR(at1500.torqueNmm / at1000.torqueNmm, 2.0 / 3.0, 1e-9);
  // Torque-to-thrust ratio: published 2.5 mm bovine drilling 1.96-2.05 mm. At the data's feed the
  // set gives 2.03 mm (BovineSetIsTheFitToThePublishedBovineRows); at Lee et al.'s lower feeds the
  // feed angle shifts it to 2.055 (0.02 mm/rev) and 2.072 mm (0.01 mm/rev), 1 % above the range.
  for (auto [f, n] : bm::LeeConditions()) {
    const bm::EdgeIntegral e = bm::IntegrateEdges(drill, set, f, n);
    std::printf("default set f %.2f n %4.0f: %.4f N, %.4f N mm, ratio %.3f mm\n", f, n, e.thrustN,
                e.torqueNmm, e.torqueNmm / e.thrustN);
    EXPECT_GT(e.torqueNmm / e.thrustN, 2.0);
    EXPECT_LT(e.torqueNmm / e.thrustN, 2.08);
  }
}

// The web half-width of the measured drill is not stated; the bovine rows cannot determine it
// (with k proportional to 1/n at one feed and one diameter, thrust and torque fix two numbers, and
// the web only trades chisel thrust against lip friction): a thinner web fits equally well with a
// higher k_f. The reference drill's 0.2 mm is kept (Docs/Calibration.md section 4).
TEST(DefaultCoefficients, PublishedRowsCannotDetermineTheWebWidth) {
  bm::CalibrationOptions shared;
  shared.chiselSharesLipCoefficients = true;
  std::array<bm::CalibrationFit, 2> fits;
  const std::array<double, 2> webs{0.2, 0.1};
  for (size_t i = 0; i < 2; ++i) {
    bm::TwistDrillParams p;
    p.webHalfWidth = webs[i];
    auto drill = std::make_shared<bm::TwistDrill>(p);
    auto rows = BovineRows();
    for (auto& r : rows)
      r.tool = drill;
    fits[i] = bm::CalibrateFit(*drill, bm::Method::Lazar, {bm::BasisTerm::InvSpindleSpeed},
                               bm::ForceModel::Default(bm::Method::Lazar, *drill), rows, shared);
    const auto& c = fits[i].model.LipCoefficients();
    std::printf(
        "web half-width %.2f mm: k_c %.2f, k_t %.2f (k_f %.3f), fit RMS %.4f N, %.4f N mm\n",
        webs[i], c.kc[0], c.kt[0], c.kt[0] / c.kc[0], fits[i].rmsThrustErrorN,
        fits[i].rmsTorqueErrorNmm);
  }
  EXPECT_NEAR(fits[0].rmsThrustErrorN, fits[1].rmsThrustErrorN, 1e-3);
  EXPECT_NEAR(fits[0].rmsTorqueErrorNmm, fits[1].rmsTorqueErrorNmm, 1e-3);
  const double kf0 = fits[0].model.LipCoefficients().kt[0] / fits[0].model.LipCoefficients().kc[0];
  const double kf1 = fits[1].model.LipCoefficients().kt[0] / fits[1].model.LipCoefficients().kc[0];
  EXPECT_NEAR(kf0, 0.323, 0.001);
  EXPECT_NEAR(kf1, 0.413, 0.001);
}

// A check outside the fitted data: MacAvelia et al. (J Biomech Eng 2012) drilled human femoral
// shaft with a 3.2 mm drill at 120 mm/min and 1000 rpm (0.12 mm/rev) and measured 140-186 N (as
// tabulated by Orelaja et al. 2020, Table 6). The bovine set under-predicts it: human cortex is
// harder than the bovine femur of the fitted rows, or their feed was lower than the 0.05 mm/rev
// assumed (Docs/Calibration.md).
TEST(DefaultCoefficients, BovineSetUnderPredictsHumanFemurAtMacAveliasCondition) {
  bm::TwistDrillParams p;
  p.radius = 1.6;
  const bm::TwistDrill drill(p);
  const bm::EdgeIntegral e =
      bm::IntegrateEdges(drill, bm::ForceModel::Default(bm::Method::Lazar, drill), 0.12, 1000);
  const bm::EdgeIntegral old =
      bm::IntegrateEdges(drill, bm::ForceModel::Assumed(bm::Method::Lazar, drill), 0.12, 1000);
  std::printf("3.2 mm drill, 0.12 mm/rev, 1000 rpm: default (bovine) set %.1f N, %.1f N mm; "
              "faieghi-assumed %.1f N, %.1f N mm (human femur: 140-186 N)\n",
              e.thrustN, e.torqueNmm, old.thrustN, old.torqueNmm);
  EXPECT_NEAR(e.thrustN, 51.9, 0.1);
  EXPECT_NEAR(old.thrustN, 69.6, 0.1);
}

} // namespace
