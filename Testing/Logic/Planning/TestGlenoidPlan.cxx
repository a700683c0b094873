// The plan on the scapula phantom: the corrected axis within 1 deg of the target, the reamer
// check against the glenoid's size, and steps that are valid scenes.
#include "bmGlenoidPlan.h"
#include "bmPlanReport.h"
#include "bmScapulaPhantom.h"
#include "bmScapulaVoxmap.h"
#include "bmScene.h"

#include <gtest/gtest.h>

using namespace bm;

namespace {
struct Planned {
  ScapulaTruth truth;
  GlenoidLandmarks landmarks;
  GlenoidMeasurements measurements;
};
Planned PlanPhantom(const ScapulaPhantomParams& p) {
  const ScapulaPhantom ph(p);
  const SegmentedBone bone(MakeScapulaVoxmap(ph, 1.0, 3));
  Planned r{ph.Truth(), DetectLandmarks(bone), {}};
  r.measurements = MeasureGlenoid(r.landmarks);
  return r;
}
} // namespace

TEST(GlenoidPlan, AxisMeetsTheTargetInTheTrueFrame) {
  const Planned d = PlanPhantom({});
  const ScapularFrame trueFrame =
      MakeScapularFrame(d.truth.glenoidCentre, d.truth.trigonum, d.truth.inferiorAngle);
  for (auto [tv, ti] : {std::pair{0.0, 0.0}, {-5.0, 3.0}, {10.0, -4.0}}) {
    PlanOptions o;
    o.targetVersionDeg = tv;
    o.targetInclinationDeg = ti;
    const GlenoidPlan plan = MakeGlenoidPlan(d.landmarks, d.measurements, o);
    // Against the phantom's analytic scapular frame (not only the measured one).
    EXPECT_NEAR(Version3DDeg(trueFrame, plan.axis), tv, 1.0);
    EXPECT_NEAR(InclinationDeg(trueFrame, plan.axis), ti, 1.0);
    EXPECT_NEAR(plan.axisVersionDeg, tv, 1e-9);
    EXPECT_NEAR(plan.axisInclinationDeg, ti, 1e-9);
    // The correction from the true face normal: the angle between the two directions.
    const Vec3 target = DirectionFromAngles(trueFrame, tv, ti);
    EXPECT_NEAR(plan.correctionDeg, AngleDeg(d.truth.faceNormal, target), 1.0);
    EXPECT_LT(Distance(plan.entry, d.truth.glenoidCentre), 1.0);
  }
}

TEST(GlenoidPlan, ReamerCheckAndSteps) {
  const Planned d = PlanPhantom({});
  PlanOptions o;
  GlenoidPlan big = MakeGlenoidPlan(d.landmarks, d.measurements, o);
  // 36.5 mm reamer on the 40 x 29 mm glenoid: (36.5 - 29) / 2 = 3.75 mm over the anterior and
  // posterior rims, none superior-inferior.
  EXPECT_FALSE(big.reamerFits);
  EXPECT_NEAR(big.reamerOverhangApMm, 3.75, 0.75);
  EXPECT_EQ(big.reamerOverhangSiMm, 0.0);
  ASSERT_FALSE(big.warnings.empty());
  o.reamerDiameterMm = 26;
  const GlenoidPlan small = MakeGlenoidPlan(d.landmarks, d.measurements, o);
  EXPECT_TRUE(small.reamerFits);
  // The guide hole reaches past the reamer's nipple: 2 + 6 + 2 mm.
  EXPECT_DOUBLE_EQ(small.pinDepthMm, 10.0);
  const nlohmann::json bone = small.CtBoneJson("ct");
  for (int i = 0; i < 2; ++i) {
    const Scene s = Scene::FromJson(small.StepSceneJson(i, bone));
    EXPECT_NEAR(AngleDeg({s.trial.axis[0], s.trial.axis[1], s.trial.axis[2]}, small.axis), 0.0,
                1e-9);
    EXPECT_NEAR(s.trial.entry[0], small.entry[0], 1e-9);
  }
  const nlohmann::json scene = small.SceneJson(bone);
  ASSERT_EQ(scene["steps"].size(), 2u);
  EXPECT_EQ(scene["steps"][0]["tool"]["type"], "drill");
  EXPECT_EQ(scene["steps"][1]["tool"]["type"], "reamer");
  EXPECT_DOUBLE_EQ(scene["steps"][0]["trial"]["depth_mm"].get<double>(), 10.0);
  // A pin shallower than the nipple's reach is warned about.
  o.pinDepthMm = 5;
  const GlenoidPlan shallow = MakeGlenoidPlan(d.landmarks, d.measurements, o);
  EXPECT_NE(shallow.warnings.front().find("nipple"), std::string::npos);
  o.pinRadiusMm = 2.5; // narrower than the 3 mm nipple
  EXPECT_THROW(MakeGlenoidPlan(d.landmarks, d.measurements, o), std::invalid_argument);
}

TEST(GlenoidPlan, ReportNamesMethodsAndFailure) {
  const Planned d = PlanPhantom(ScapulaPhantomParams::B2());
  const GlenoidPlan plan = MakeGlenoidPlan(d.landmarks, d.measurements);
  PlanReportInput in;
  in.source = "phantom";
  in.landmarks = &d.landmarks;
  in.measurements = &d.measurements;
  in.plan = &plan;
  const std::string md = PlanReportMarkdown(in);
  EXPECT_NE(md.find("Friedman"), std::string::npos);
  EXPECT_NE(md.find("two-plane"), std::string::npos);
  EXPECT_EQ(PlanReportJson(in)["status"], "planned");
  const std::string html = PlanReportHtml(in);
  EXPECT_NE(html.find("<td>version, 3D</td>"), std::string::npos);
  EXPECT_NE(html.find("</html>"), std::string::npos);
  PlanReportInput none;
  none.source = "head CT";
  none.failure = "no glenoid found";
  EXPECT_EQ(PlanReportJson(none)["status"], "no_glenoid");
  EXPECT_NE(PlanReportMarkdown(none).find("trigonum_mm"), std::string::npos);
  EXPECT_EQ(PlanReportMarkdown(none).find(".png"), std::string::npos);
  none.failurePicture = "plan_failure.png";
  EXPECT_NE(PlanReportMarkdown(none).find("](plan_failure.png)"), std::string::npos);
  EXPECT_NE(PlanReportHtml(none).find("<img src=\"plan_failure.png\""), std::string::npos);
  EXPECT_EQ(PlanReportJson(none)["picture"], "plan_failure.png");
}
