// Coefficient sets (bmForceModel.h): every set names itself and says whether it is calibrated;
// scenes name a set by file or by shipped name; the spindle-speed basis term makes forces fall
// with speed; the shipped calibrated drilling set reproduces its published data.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "bmCalibration.h"
#include "bmFeedTrial.h"
#include "bmForceModel.h"
#include "bmMachiningSetup.h"
#include "bmScene.h"
#include "bmToolModel.h"

namespace {

TEST(CoefficientSets, BuiltInSetsAreNamedAndSayWhetherCalibrated) {
  const bm::TwistDrill drill;
  const bm::ArcLipTool reamer;
  struct Case {
    bm::ForceModel model;
    const char* name;
    bool calibrated;
  };
  const Case cases[] = {
      {bm::ForceModel::Default(bm::Method::Lazar, drill), "drilling-bovine-orelaja2020", true},
      {bm::ForceModel::Default(bm::Method::Zheng, drill), "zheng-fit-to-faieghi-assumed", false},
      {bm::ForceModel::Default(bm::Method::Lazar, reamer), "faieghi-assumed", false},
      {bm::ForceModel::Assumed(bm::Method::Lazar, drill), "faieghi-assumed", false},
      {bm::ForceModel::Assumed(bm::Method::Zheng, drill), "zheng-fit-to-faieghi-assumed", false}};
  for (const Case& c : cases) {
    const bm::ForceModel& d = c.model;
    EXPECT_EQ(d.Provenance().name, c.name);
    EXPECT_EQ(d.Provenance().calibrated, c.calibrated) << c.name;
    EXPECT_FALSE(d.Provenance().source.empty());
    const nlohmann::json j = d.ToJson();
    EXPECT_EQ(j.at("name"), d.Provenance().name);
    EXPECT_EQ(j.at("calibrated"), c.calibrated);
    const bm::ForceModel back = bm::ForceModel::FromJson(j, drill);
    EXPECT_EQ(back.Provenance().name, d.Provenance().name);
    EXPECT_EQ(back.LipCoefficients().kc, d.LipCoefficients().kc);
    EXPECT_EQ(back.ChiselCoefficients().kt, d.ChiselCoefficients().kt);
  }
  // The built-in default drilling set is the shipped file of the same name.
  const bm::ForceModel file =
      bm::ForceModel::FromJson({{"coefficients", "drilling-bovine-orelaja2020"}}, drill);
  EXPECT_EQ(file.LipCoefficients().kc, cases[0].model.LipCoefficients().kc);
  EXPECT_EQ(file.LipCoefficients().kt, cases[0].model.LipCoefficients().kt);
  EXPECT_EQ(file.ChiselCoefficients().kc, cases[0].model.ChiselCoefficients().kc);
  EXPECT_EQ(file.Provenance().source, cases[0].model.Provenance().source);
  // Drilling coefficients on another tool say so.
  EXPECT_NE(cases[2].model.Provenance().source.find("reamer"), std::string::npos);
}

TEST(CoefficientSets, CustomCoefficientsWithoutAProvenanceAreUnnamedAndUncalibrated) {
  const bm::TwistDrill drill;
  nlohmann::json j = bm::ForceModel::Default(bm::Method::Lazar, drill).ToJson();
  j.erase("name");
  j.erase("calibrated");
  j.erase("source");
  const bm::ForceModel m = bm::ForceModel::FromJson(j, drill);
  EXPECT_EQ(m.Provenance().name, "unnamed");
  EXPECT_FALSE(m.Provenance().calibrated);
}

TEST(CoefficientSets, SceneNamesACoefficientFileByPath) {
  const bm::TwistDrill drill;
  bm::ForceModel m = bm::ForceModel::Default(bm::Method::Lazar, drill);
  bm::Coefficients c = m.LipCoefficients();
  c.kc[0] = 1234.5;
  m.SetLipCoefficients(c);
  m.SetProvenance({"test-set", true, "unit test"});
  const auto path = std::filesystem::temp_directory_path() / "bm_test_coefficients.json";
  std::ofstream(path) << m.ToJson().dump(2);
  const bm::ForceModel loaded = bm::ForceModel::FromJson({{"coefficients", path.string()}}, drill);
  EXPECT_EQ(loaded.LipCoefficients().kc[0], 1234.5);
  EXPECT_EQ(loaded.Provenance().name, "test-set");
  EXPECT_TRUE(loaded.Provenance().calibrated);
  EXPECT_THROW(
      bm::ForceModel::FromJson({{"coefficients", path.string()}, {"method", "zheng"}}, drill),
      std::invalid_argument);
  EXPECT_THROW(bm::ForceModel::FromJson(
                   {{"coefficients", path.string()}, {"lips", nlohmann::json()}}, drill),
               std::invalid_argument);
  try {
    bm::ForceModel::FromJson({{"coefficients", "no-such-set"}}, drill);
    ADD_FAILURE() << "no error for a missing set";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no coefficient set named 'no-such-set'"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(bm::ForceModel::FromJson({{"coefficients", "/no/such/file.json"}}, drill),
               std::invalid_argument);
}

TEST(CoefficientSets, SpindleSpeedTermMakesForcesFallWithSpeed) {
  const bm::TwistDrill drill;
  const bm::ForceModel d = bm::ForceModel::Default(bm::Method::Lazar, drill);
  const bm::ForceModel m(
      bm::Method::Lazar,
      {{bm::BasisTerm::One, bm::BasisTerm::InvSpindleSpeed}, {400.0, 500.0}, {200.0, 250.0}},
      d.ChiselCoefficients());
  // At 1000 rpm the term is 1: k_c = 900, k_t = 450 on the lips.
  const bm::ElementTerms t = m.Terms(drill, bm::EdgeKind::Lip, 1.0, 0.02, 1000);
  ASSERT_EQ(t.g.size(), 2u);
  EXPECT_DOUBLE_EQ(t.g[1], 1.0);
  EXPECT_DOUBLE_EQ(m.Terms(drill, bm::EdgeKind::Lip, 1.0, 0.02, 2000).g[1], 0.5);
  double last = 1e300;
  for (double n : {500.0, 1000.0, 1500.0, 3000.0}) {
    const bm::EdgeIntegral e = bm::IntegrateEdges(drill, m, 0.02, n);
    std::printf("n %5.0f rpm: thrust %.4f N, torque %.4f N mm\n", n, e.thrustN, e.torqueNmm);
    EXPECT_LT(e.thrustN, last);
    last = e.thrustN;
  }
}

} // namespace

namespace {

// The reaming set is an assumption (Docs/Calibration.md): the assumed drilling set scaled so that
// the glenoid reamer, fully engaged at the glenoid scene's 0.1 mm/rev and 500 rpm, needs 25 N of
// thrust, the top of the hand-applied drilling forces reported for operators (peak 6-24 N).
TEST(CoefficientSets, ReamingAssumedSetAimsAtHandForces) {
  const bm::ArcLipTool reamer;
  const bm::ForceModel drillSet = bm::ForceModel::Assumed(bm::Method::Lazar, reamer);
  const bm::ForceModel ream =
      bm::ForceModel::FromJson({{"coefficients", "reaming-assumed"}}, reamer);
  EXPECT_EQ(ream.Provenance().name, "reaming-assumed");
  EXPECT_FALSE(ream.Provenance().calibrated);
  const bm::EdgeIntegral before = bm::IntegrateEdges(reamer, drillSet, 0.1, 500);
  const bm::EdgeIntegral after = bm::IntegrateEdges(reamer, ream, 0.1, 500);
  std::printf(
      "glenoid reamer at 0.1 mm/rev, 500 rpm, fully engaged: drilling set %.2f N, %.1f N mm;"
      " reaming-assumed %.2f N, %.1f N mm\n",
      before.thrustN, before.torqueNmm, after.thrustN, after.torqueNmm);
  EXPECT_NEAR(after.thrustN, 25.0, 0.25);
  EXPECT_GT(after.torqueNmm, 0.0);
}

} // namespace

namespace {

// End to end: a scene names the calibrated drilling set, the engine cuts with it (its basis has
// the spindle-speed term), and the steady thrust and torque match the set's own quadrature
// reference at the scene's feed and speed; at 1500 rpm they are two thirds of the 1000 rpm ones.
TEST(CoefficientSets, SceneCutsWithANamedCalibratedSet) {
  std::array<double, 2> thrust{}, torque{};
  int k = 0;
  for (const double rpm : {1000.0, 1500.0}) {
    bm::Scene s;
    s.shellResolution = 256;
    s.voxmapResolution = 64;
    s.threads = 2;
    s.trial.frameS = 0.004;
    s.trial.speedRpm = rpm;
    s.forceModel = {{"coefficients", "drilling-bovine-orelaja2020"}};
    bm::MachiningSetup setup(s, bm::MakeSceneBlock(s));
    EXPECT_EQ(setup.Model().Provenance().name, "drilling-bovine-orelaja2020");
    EXPECT_TRUE(setup.Model().Provenance().calibrated);
    bm::FeedTrial trial(setup);
    ASSERT_TRUE(trial.Run());
    const nlohmann::json sum = trial.Summary();
    const bm::EdgeIntegral ref =
        bm::IntegrateEdges(setup.Tool(), setup.Model(), s.trial.feedMmPerRev, rpm);
    thrust[k] = sum.at("thrust_N").get<double>();
    torque[k] = sum.at("torque_Nmm").get<double>();
    std::printf("scene with drilling-bovine-orelaja2020 at %.0f rpm: %.4f N (reference %.4f), "
                "%.4f N mm (reference %.4f)\n",
                rpm, thrust[k], ref.thrustN, torque[k], ref.torqueNmm);
    EXPECT_NEAR(thrust[k], ref.thrustN, 0.02 * ref.thrustN);
    EXPECT_NEAR(torque[k], ref.torqueNmm, 0.02 * ref.torqueNmm);
    ++k;
  }
  EXPECT_NEAR(thrust[1] / thrust[0], 2.0 / 3.0, 0.01);
  EXPECT_NEAR(torque[1] / torque[0], 2.0 / 3.0, 0.01);
}

} // namespace
