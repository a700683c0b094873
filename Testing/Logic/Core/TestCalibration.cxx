// Calibration (bmCalibration.h): known coefficients are recovered from noiseless synthetic
// entry-phase curves, and leave-one-condition-out cross-validation reports one fold per condition
// (the paper's four conditions on the assumed set "faieghi-assumed", which it reproduces).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bmCalibration.h"
#include "bmToolModel.h"

namespace {

void ExpectRelNear(double got, double want, double rel, const char* what) {
  EXPECT_NEAR(got, want, rel * std::abs(want)) << what;
}

void CheckRecovers(bm::Method method, const bm::Coefficients& truth) {
  const bm::TwistDrill drill;
  const bm::ForceModel chisel = bm::ForceModel::Default(method, drill);
  const bm::ForceModel model(method, truth, chisel.ChiselCoefficients());
  const auto samples = bm::EntryCurves(drill, model, bm::LeeConditions(), 20);
  ASSERT_EQ(samples.size(), 80u);
  const bm::ForceModel fit = bm::Calibrate(drill, method, truth.basis, chisel, samples);
  ASSERT_EQ(fit.LipCoefficients().kc.size(), truth.kc.size());
  for (size_t i = 0; i < truth.kc.size(); ++i) {
    std::printf("%s %-16s kc %.9g (true %.9g)  kt %.9g (true %.9g)\n", bm::ToString(method).c_str(),
                bm::ToString(truth.basis[i]).c_str(), fit.LipCoefficients().kc[i], truth.kc[i],
                fit.LipCoefficients().kt[i], truth.kt[i]);
    ExpectRelNear(fit.LipCoefficients().kc[i], truth.kc[i], 1e-6, "kc");
    ExpectRelNear(fit.LipCoefficients().kt[i], truth.kt[i], 1e-6, "kt");
  }
  EXPECT_EQ(fit.GetMethod(), method);
  EXPECT_EQ(fit.ChiselCoefficients().kc, chisel.ChiselCoefficients().kc);
}

TEST(Calibration, RecoversKnownLazarCoefficients) {
  CheckRecovers(
      bm::Method::Lazar,
      {{bm::BasisTerm::One, bm::BasisTerm::OneMinusSinGamma}, {812.5, 333.25}, {401.0, 95.5}});
}

TEST(Calibration, RecoversKnownZhengCoefficients) {
  CheckRecovers(
      bm::Method::Zheng,
      {{bm::BasisTerm::One, bm::BasisTerm::InvCuttingSpeed}, {1200.0, 45.0}, {600.0, 12.5}});
}

TEST(Calibration, CrossValidationReportsOneFoldPerConditionNearZeroOnNoiselessData) {
  const bm::TwistDrill drill;
  const bm::ForceModel model = bm::ForceModel::Assumed(bm::Method::Lazar, drill);
  const auto samples = bm::EntryCurves(drill, model, bm::LeeConditions(), 12);
  const auto folds =
      bm::CrossValidate(drill, bm::Method::Lazar, model.LipCoefficients().basis, model, samples);
  ASSERT_EQ(folds.size(), 4u);
  const auto conditions = bm::LeeConditions();
  for (const auto& fold : folds) {
    std::printf("fold f %.2f n %4.0f: rms thrust error %.3g N, torque error %.3g N mm, torque min "
                "%.3f mean %.3f\n",
                fold.feedMmPerRev, fold.speedRpm, fold.rmsThrustErrorN, fold.rmsTorqueErrorNmm,
                fold.minPredictedTorqueNmm, fold.meanPredictedTorqueNmm);
    EXPECT_NE(std::find(conditions.begin(), conditions.end(),
                        std::pair{fold.feedMmPerRev, fold.speedRpm}),
              conditions.end());
    EXPECT_TRUE(std::isfinite(fold.rmsThrustErrorN));
    EXPECT_TRUE(std::isfinite(fold.rmsTorqueErrorNmm));
    EXPECT_LT(fold.rmsThrustErrorN, 1e-6);
    EXPECT_LT(fold.rmsTorqueErrorNmm, 1e-6);
    EXPECT_GT(fold.minPredictedTorqueNmm, 0.0);
    for (size_t i = 0; i < model.LipCoefficients().kc.size(); ++i)
      ExpectRelNear(fold.model.LipCoefficients().kc[i], model.LipCoefficients().kc[i], 1e-6,
                    "fold kc");
  }
}

TEST(Calibration, NoiseShowsUpInTheFoldErrors) {
  const bm::TwistDrill drill;
  const bm::ForceModel model = bm::ForceModel::Assumed(bm::Method::Lazar, drill);
  int k = 0;
  const auto samples =
      bm::EntryCurves(drill, model, bm::LeeConditions(), 12, [&](bm::CalibrationSample& s) {
        s.thrustN *= 1.0 + 0.05 * ((k++ % 3) - 1); // deterministic +-5 % scatter
      });
  const auto folds =
      bm::CrossValidate(drill, bm::Method::Lazar, model.LipCoefficients().basis, model, samples);
  ASSERT_EQ(folds.size(), 4u);
  for (const auto& fold : folds) {
    EXPECT_TRUE(std::isfinite(fold.rmsThrustErrorN));
    EXPECT_GT(fold.rmsThrustErrorN, 1e-3);
  }
}

TEST(Calibration, RejectsUnderdeterminedInput) {
  const bm::TwistDrill drill;
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, drill);
  EXPECT_THROW(bm::Calibrate(drill, bm::Method::Lazar, {}, model, {}), std::invalid_argument);
  // One sample (a thrust and a torque) cannot determine four coefficients.
  const std::vector<bm::BasisTerm> two{bm::BasisTerm::One, bm::BasisTerm::OneMinusSinGamma};
  const auto one = bm::EntryCurves(drill, model, {{0.02, 1000}}, 1);
  EXPECT_THROW(bm::Calibrate(drill, bm::Method::Lazar, two, model, one), std::invalid_argument);
  // At a single speed the terms 1 and 1000 / n are the same column: the rank check refuses.
  const auto sameSpeed = bm::EntryCurves(drill, model, {{0.01, 1000}, {0.02, 1000}}, 4);
  EXPECT_THROW(bm::Calibrate(drill, bm::Method::Lazar,
                             {bm::BasisTerm::One, bm::BasisTerm::InvSpindleSpeed}, model,
                             sameSpeed),
               std::invalid_argument);
  EXPECT_THROW(bm::CrossValidate(drill, bm::Method::Lazar, model.LipCoefficients().basis, model,
                                 bm::EntryCurves(drill, model, {{0.02, 1000}}, 5)),
               std::invalid_argument);
}

} // namespace
