// Calibration from a data file (bmCalibrationData.h): a synthetic set with known coefficients,
// several tools, speeds, bones with unknown material factors and a scaled chisel, written as CSV
// and read back, is recovered within 1 %; bad files are refused with the line and column named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bmCalibration.h"
#include "bmCalibrationData.h"
#include "bmToolModel.h"

namespace {

std::filesystem::path TempFile(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "bm_calibration_data_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

// Truth: k = a + b 1000/n on the lips, chisel at 1.3 x the built-in, bone factors 1, 0.55, 0.3.
const bm::Coefficients kTruth{
    {bm::BasisTerm::One, bm::BasisTerm::InvSpindleSpeed}, {900.0, 700.0}, {650.0, 520.0}};
constexpr double kChiselScale = 1.3;
const std::vector<std::pair<std::string, double>> kBones{
    {"bovine", 1.0}, {"porcine", 0.55}, {"artificial", 0.3}};

std::vector<bm::CalibrationRecord> SyntheticRecords() {
  const bm::TwistDrill ref;
  bm::Coefficients chisel = bm::ForceModel::Default(bm::Method::Lazar, ref).ChiselCoefficients();
  for (double& v : chisel.kc)
    v *= kChiselScale;
  for (double& v : chisel.kt)
    v *= kChiselScale;
  const bm::ForceModel truth(bm::Method::Lazar, kTruth, chisel);
  std::vector<bm::CalibrationRecord> out;
  for (const double d : {2.5, 3.2})
    for (const auto& [bone, factor] : kBones)
      for (const double n : {800.0, 1000.0, 1500.0})
        for (const double f : {0.03, 0.08}) {
          bm::CalibrationRecord r;
          r.toolSpec = {{"type", "drill"}, {"radius_mm", d / 2}};
          r.sample.tool = std::shared_ptr<const bm::ToolModel>(bm::MakeTool(r.toolSpec));
          r.sample.feedMmPerRev = f;
          r.sample.speedRpm = n;
          r.sample.depthMm = 1e300;
          r.sample.bone = bone;
          const bm::EdgeIntegral p = bm::Predict(ref, truth, r.sample, factor);
          r.sample.thrustN = p.thrustN;
          r.sample.torqueNmm = p.torqueNmm;
          r.source = "synthetic, \"known\" coefficients";
          out.push_back(r);
        }
  return out;
}

TEST(CalibrationData, SyntheticSetThroughCsvRecoversKnownCoefficientsWithinOnePercent) {
  const auto file = TempFile("synthetic.csv", bm::FormatCalibrationCsv(SyntheticRecords()));
  const auto records = bm::ReadCalibrationCsv(file);
  ASSERT_EQ(records.size(), 36u);
  EXPECT_EQ(records[0].source, "synthetic, \"known\" coefficients");
  EXPECT_NEAR(records[0].sample.tool->OuterRadius(), 1.25, 1e-12);
  const bm::TwistDrill ref;
  bm::CalibrationOptions options;
  options.fitBoneFactors = true;
  options.fitChiselScale = true;
  const bm::CalibrationFit fit = bm::CalibrateFit(ref, bm::Method::Lazar, kTruth.basis,
                                                  bm::ForceModel::Default(bm::Method::Lazar, ref),
                                                  bm::SamplesOf(records), options);
  const auto& c = fit.model.LipCoefficients();
  for (size_t i = 0; i < kTruth.kc.size(); ++i) {
    std::printf("%-16s kc %.6g (true %.6g)  kt %.6g (true %.6g)\n",
                bm::ToString(c.basis[i]).c_str(), c.kc[i], kTruth.kc[i], c.kt[i], kTruth.kt[i]);
    EXPECT_NEAR(c.kc[i], kTruth.kc[i], 0.01 * kTruth.kc[i]);
    EXPECT_NEAR(c.kt[i], kTruth.kt[i], 0.01 * kTruth.kt[i]);
  }
  std::printf("chisel scale %.6g (true %.6g), %d alternations\n", fit.chiselScale, kChiselScale,
              fit.iterations);
  EXPECT_NEAR(fit.chiselScale, kChiselScale, 0.01 * kChiselScale);
  EXPECT_EQ(fit.referenceBone, "bovine");
  for (const auto& [bone, factor] : kBones) {
    std::printf("bone %-10s factor %.6g (true %.6g)\n", bone.c_str(), fit.boneFactor.at(bone),
                factor);
    EXPECT_NEAR(fit.boneFactor.at(bone), factor, 0.01 * factor) << bone;
  }
  EXPECT_LT(fit.rmsThrustErrorN, 1e-3);
  EXPECT_TRUE(fit.model.Provenance().calibrated);
}

TEST(CalibrationData, CrossValidationHoldsOutOneConditionPerFold) {
  auto records = SyntheticRecords();
  const bm::TwistDrill ref;
  bm::CalibrationOptions options;
  options.fitBoneFactors = true;
  options.fitChiselScale = true;
  // Give every record its condition label as the reader would.
  const auto file = TempFile("cv.csv", bm::FormatCalibrationCsv(records));
  const auto samples = bm::SamplesOf(bm::ReadCalibrationCsv(file));
  const auto folds =
      bm::CrossValidate(ref, bm::Method::Lazar, kTruth.basis,
                        bm::ForceModel::Default(bm::Method::Lazar, ref), samples, options);
  ASSERT_EQ(folds.size(), 36u); // 2 drills x 3 bones x 3 speeds x 2 feeds, one row each
  for (const auto& f : folds) {
    ASSERT_EQ(f.sampleIndex.size(), 1u);
    EXPECT_TRUE(f.boneFactorKnown);
    EXPECT_LT(f.rmsThrustErrorN, 1e-3 * samples[f.sampleIndex[0]].thrustN) << f.condition;
    EXPECT_GT(f.minPredictedTorqueNmm, 0) << f.condition;
  }
}

// A known density (the engine's voxel material) scales a row's forces; rows at two densities and
// one bone label determine the coefficients without any fitted factor.
TEST(CalibrationData, DensityColumnScalesTheForcesItIsGiven) {
  auto records = SyntheticRecords();
  std::erase_if(records, [](const bm::CalibrationRecord& r) { return r.sample.bone != "bovine"; });
  const bm::TwistDrill ref;
  bm::Coefficients chisel = bm::ForceModel::Default(bm::Method::Lazar, ref).ChiselCoefficients();
  for (double& v : chisel.kc)
    v *= kChiselScale;
  for (double& v : chisel.kt)
    v *= kChiselScale;
  const bm::ForceModel truth(bm::Method::Lazar, kTruth, chisel);
  for (size_t i = 0; i < records.size(); i += 2) {
    bm::CalibrationSample& s = records[i].sample;
    s.material = 0.4;
    const bm::EdgeIntegral p = bm::Predict(ref, truth, s);
    s.thrustN = p.thrustN;
    s.torqueNmm = p.torqueNmm;
  }
  const auto file = TempFile("density.csv", bm::FormatCalibrationCsv(records));
  const auto back = bm::ReadCalibrationCsv(file);
  ASSERT_EQ(back.size(), records.size());
  EXPECT_DOUBLE_EQ(back[0].sample.material, 0.4);
  EXPECT_DOUBLE_EQ(back[1].sample.material, 1.0);
  EXPECT_NE(back[0].sample.condition, back[1].sample.condition);
  bm::CalibrationOptions options;
  options.fitChiselScale = true;
  const bm::CalibrationFit fit = bm::CalibrateFit(ref, bm::Method::Lazar, kTruth.basis,
                                                  bm::ForceModel::Default(bm::Method::Lazar, ref),
                                                  bm::SamplesOf(back), options);
  for (size_t i = 0; i < kTruth.kc.size(); ++i) {
    EXPECT_NEAR(fit.model.LipCoefficients().kc[i], kTruth.kc[i], 1e-6 * kTruth.kc[i]);
    EXPECT_NEAR(fit.model.LipCoefficients().kt[i], kTruth.kt[i], 1e-6 * kTruth.kt[i]);
  }
  EXPECT_NEAR(fit.chiselScale, kChiselScale, 1e-6);
  // Read as density 1, the same numbers fit worse.
  auto wrong = bm::SamplesOf(back);
  for (auto& s : wrong)
    s.material = 1.0;
  const bm::CalibrationFit bad =
      bm::CalibrateFit(ref, bm::Method::Lazar, kTruth.basis,
                       bm::ForceModel::Default(bm::Method::Lazar, ref), wrong, options);
  std::printf("RMS thrust error with the density column %.3g N, ignoring it %.3g N\n",
              fit.rmsThrustErrorN, bad.rmsThrustErrorN);
  EXPECT_GT(bad.rmsThrustErrorN, 1000 * std::max(fit.rmsThrustErrorN, 1e-9));
}

TEST(CalibrationData, ShippedPublishedSetReadsWithACitationPerRow) {
  const auto records = bm::ReadCalibrationCsv(std::filesystem::path(BM_SOURCE_DIR) /
                                              "Resources/Calibration/drilling-published.csv");
  ASSERT_GE(records.size(), 6u);
  for (const auto& r : records) {
    EXPECT_FALSE(r.source.empty()) << "line " << r.line;
    EXPECT_FALSE(r.note.empty()) << "line " << r.line;
    EXPECT_GT(r.sample.thrustN, 0) << "line " << r.line;
  }
}

TEST(CalibrationData, BadFilesNameTheLineAndColumn) {
  auto expectError = [](const std::string& text, const std::string& needle) {
    const auto file = TempFile("bad.csv", text);
    try {
      bm::ReadCalibrationCsv(file);
      ADD_FAILURE() << "no error for: " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectError("tool,feed_mm_per_rev,speed_rpm,thrust_N,colour\n", "unknown column 'colour'");
  expectError("tool,feed_mm_per_rev,thrust_N\n", "missing required column 'speed_rpm'");
  expectError("tool,feed_mm_per_rev,speed_rpm,thrust_N\ndrill,0.05,1000,abc\n",
              "bad.csv:2 column thrust_N: 'abc' is not a number");
  expectError("tool,feed_mm_per_rev,speed_rpm,thrust_N\ndrill,-0.05,1000,5\n",
              "column feed_mm_per_rev: -0.05 is out of range");
  expectError("tool,feed_mm_per_rev,speed_rpm,thrust_N\nspoon,0.05,1000,5\n",
              "unknown tool 'spoon'");
  expectError("tool,feed_mm_per_rev,speed_rpm,thrust_N\ndrill,0.05,1000\n", "3 fields");
  expectError("tool,feed_mm_per_rev,speed_rpm,thrust_N\n", "no data rows");
  expectError("tool,feed_mm_per_rev,speed_rpm,thrust_N,source\ndrill,0.05,1000,5,\"open\n",
              "unterminated quote");
}

} // namespace
