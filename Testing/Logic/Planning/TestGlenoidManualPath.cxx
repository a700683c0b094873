// The plan when detection is not enough (Docs/Planning.md, "Landmarks" and "The plan"): a scan that
// misses part of the scapula, a glenoid placed by hand (centre and normal, or rim points), a
// normal placed the wrong way round, a chosen side, implausible results flagged, and the step
// scenes reading the CT with the plan's import settings, a tool that would start inside bone. On
// the scapula phantom sampled at 1 mm.
#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmGlenoidPlan.h"
#include "bmPlanReport.h"
#include "bmScapulaPhantom.h"
#include "bmScapulaVoxmap.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace bm;

namespace {

/// The phantom's voxmap with the bone below world z = zCut removed (the scan's lower edge).
Voxmap CutBelow(const ScapulaPhantom& ph, double zCut) {
  Voxmap v = MakeScapulaVoxmap(ph, 1.0, 3);
  const auto& d = v.Dims();
  for (int k = 0; k < d[2]; ++k) {
    if (v.Origin()[2] + k * v.Spacing() >= zCut)
      continue;
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        v.SetFill(v.Index(i, j, k), 0);
  }
  return v;
}

/// The voxmap's bounds, world mm, with the lower z edge at zCut.
Box3 ScanBox(const Voxmap& v, double zCut) {
  Box3 b;
  for (size_t a = 0; a < 3; ++a) {
    b.lo[a] = v.Origin()[a] - 0.5 * v.Spacing();
    b.hi[a] = b.lo[a] + v.Dims()[a] * v.Spacing();
  }
  b.lo[2] = zCut;
  return b;
}

/// The phantom's bone with the field of view ending 45 mm below the glenoid centre: the
/// inferior angle (115 mm below) is outside it, and the bone there ends at the scan's edge; the
/// detection options know that edge.
struct CutScan {
  ScapulaTruth truth;
  SegmentedBone bone;
  DetectionOptions options;
};
CutScan ScanWithoutTheInferiorAngle() {
  const ScapulaPhantom ph{ScapulaPhantomParams{}};
  const double zCut = ph.Truth().glenoidCentre[2] - 45;
  const Voxmap v = CutBelow(ph, zCut);
  DetectionOptions o;
  o.scanBounds = ScanBox(v, zCut);
  return {ph.Truth(), SegmentedBone(v), o};
}

} // namespace

TEST(GlenoidManualPath, AScanThatMissesTheInferiorAngleStillPlans) {
  const CutScan scan = ScanWithoutTheInferiorAngle();
  const ScapulaTruth& t = scan.truth;
  const SegmentedBone& bone = scan.bone;
  const GlenoidLandmarks L = DetectLandmarks(bone, {}, scan.options);
  EXPECT_LT(Distance(L.glenoidCentre, t.glenoidCentre), 1.0);
  EXPECT_TRUE(L.HasTrigonum());
  ASSERT_FALSE(L.HasInferiorAngle());
  EXPECT_NE(L.inferiorMissing.find("inferior edge"), std::string::npos) << L.inferiorMissing;
  EXPECT_EQ(L.side, "right");
  const GlenoidMeasurements m = MeasureGlenoid(L);
  EXPECT_FALSE(m.hasFrame);
  EXPECT_TRUE(std::isnan(m.version3DDeg));
  EXPECT_TRUE(std::isnan(m.inclinationDeg));
  EXPECT_FALSE(m.Available("version_3d_deg"));
  EXPECT_NE(m.notAvailable.at("version_3d_deg").find("inferior angle"), std::string::npos);
  // What does not need the scapular plane is still measured.
  EXPECT_NEAR(m.friedmanVersionDeg, t.friedmanVersionDeg, 1.0);
  EXPECT_NEAR(m.widthMm, t.glenoidWidthMm, 1.5);
  // The plan: along the face normal, uncorrected, saying why.
  const GlenoidPlan plan = MakeGlenoidPlan(L, m);
  EXPECT_FALSE(plan.corrected);
  EXPECT_LT(AngleDeg(plan.axis, t.faceNormal), 1.0);
  EXPECT_DOUBLE_EQ(plan.correctionDeg, 0.0);
  ASSERT_FALSE(plan.warnings.empty());
  EXPECT_NE(plan.warnings.front().find("no correction"), std::string::npos);
  // The plan's JSON and reports carry "not available" with the reason, never a number.
  const nlohmann::json mj = m.ToJson();
  EXPECT_TRUE(mj["version_3d_deg"].is_null());
  EXPECT_TRUE(mj.contains("not_available"));
  EXPECT_FALSE(mj.contains("scapular_frame"));
  const nlohmann::json lj = L.ToJson();
  EXPECT_FALSE(lj.contains("inferior_angle_mm"));
  EXPECT_TRUE(lj["not_available"].contains("inferior_angle"));
  EXPECT_NO_THROW(LandmarkOverrides::FromJson(lj)); // the plan's landmarks read back
  PlanReportInput in;
  in.landmarks = &L;
  in.measurements = &m;
  in.plan = &plan;
  const std::string md = PlanReportMarkdown(in);
  EXPECT_NE(md.find("not available"), std::string::npos);
  EXPECT_EQ(md.find("nan"), std::string::npos) << md;
  // The same scan without its bounds known takes the cut edge for the inferior angle: the
  // bounds are what tell the two apart.
  const GlenoidLandmarks blind = DetectLandmarks(bone);
  EXPECT_TRUE(blind.HasInferiorAngle());
}

TEST(GlenoidManualPath, ACentreAndNormalAloneMakeAPlan) {
  const CutScan scan = ScanWithoutTheInferiorAngle();
  const ScapulaTruth& t = scan.truth;
  const SegmentedBone& bone = scan.bone;
  const DetectionOptions& o = scan.options;
  LandmarkOverrides ov;
  ov.glenoidCentre = AddScaled(t.glenoidCentre, t.anteriorAxis, 1.0); // placed 1 mm off
  ov.faceNormal = t.faceNormal;
  const GlenoidLandmarks L = DetectLandmarks(bone, ov, o);
  EXPECT_EQ(L.centreSource, "user");
  EXPECT_FALSE(L.HasInferiorAngle());
  const GlenoidMeasurements m = MeasureGlenoid(L);
  const GlenoidPlan plan = MakeGlenoidPlan(L, m);
  EXPECT_LT(AngleDeg(plan.axis, t.faceNormal), 1e-9);
  EXPECT_LT(Distance(plan.entry, *ov.glenoidCentre), 1e-9);
  EXPECT_GT(plan.clearanceMm, 1.0);
  // With the scapular landmarks placed too, the axis is corrected to the target.
  LandmarkOverrides all = ov;
  all.trigonum = t.trigonum;
  all.inferiorAngle = t.inferiorAngle;
  const GlenoidLandmarks L2 = DetectLandmarks(bone, all, o);
  const GlenoidPlan corrected = MakeGlenoidPlan(L2, MeasureGlenoid(L2));
  EXPECT_TRUE(corrected.corrected);
  EXPECT_NEAR(corrected.correctionDeg, AngleDeg(t.faceNormal, t.lateralAxis), 1.0);
}

TEST(GlenoidManualPath, ANormalIntoTheBoneIsRefused) {
  const ScapulaPhantom ph{ScapulaPhantomParams{}};
  const ScapulaTruth& t = ph.Truth();
  const SegmentedBone bone(MakeScapulaVoxmap(ph, 1.0, 3));
  LandmarkOverrides ov;
  ov.glenoidCentre = t.glenoidCentre;
  ov.faceNormal = Scale(t.faceNormal, -1);
  try {
    DetectLandmarks(bone, ov);
    FAIL() << "a normal into the bone was accepted";
  } catch (const NoGlenoidFound& e) {
    EXPECT_NE(std::string(e.what()).find("points into the bone"), std::string::npos) << e.what();
  }
  ov.faceNormal = t.faceNormal; // the right way round
  EXPECT_NO_THROW(DetectLandmarks(bone, ov));
}

TEST(GlenoidManualPath, RimPointsPlaceTheGlenoid) {
  const ScapulaPhantom ph{ScapulaPhantomParams{}};
  const ScapulaTruth& t = ph.Truth();
  const SegmentedBone bone(MakeScapulaVoxmap(ph, 1.0, 3));
  // Four clicks on the rim (the truth's rim plane, at the face's half axes), not in order.
  const Vec3 up =
      Normalized(AddScaled(t.superiorAxis, t.faceNormal, -Dot(t.superiorAxis, t.faceNormal)));
  const Vec3 across = Cross(t.faceNormal, up);
  LandmarkOverrides ov;
  for (const auto& [u, w] : {std::pair{19.0, 0.0}, {0.0, 14.0}, {0.0, -14.0}, {-19.0, 0.0}})
    ov.rimPoints.push_back(AddScaled(AddScaled(t.glenoidCentre, up, u), across, w));
  const GlenoidLandmarks L = DetectLandmarks(bone, ov);
  EXPECT_EQ(L.centreSource, "user rim");
  EXPECT_LT(Distance(L.glenoidCentre, t.glenoidCentre), 1.0);
  EXPECT_LT(AngleDeg(L.faceNormal, t.faceNormal), 1.0);
  // From JSON: at least three points; points on a line are refused.
  EXPECT_THROW(LandmarkOverrides::FromJson({{"rim_points_mm", {{1, 2, 3}, {4, 5, 6}}}}),
               std::invalid_argument);
  LandmarkOverrides line;
  for (double s : {-10.0, 0.0, 10.0})
    line.rimPoints.push_back(AddScaled(t.glenoidCentre, up, s));
  EXPECT_THROW(DetectLandmarks(bone, line), NoGlenoidFound);
}

TEST(GlenoidManualPath, AClickOnTheFaceGivesTheGlenoid) {
  // The scapula alone (the humeral head removed: no joint to find), as a preview that keeps one
  // bone. A click on the face, 4 mm off its centre, gives the glenoid as detection would: the
  // centre and normal come from the rim traced around the face's own normal.
  const ScapulaPhantom ph{ScapulaPhantomParams{}};
  const ScapulaTruth& t = ph.Truth();
  Voxmap v = MakeScapulaVoxmap(ph, 1.0, 3);
  for (int k = 0; k < v.Dims()[2]; ++k)
    for (int j = 0; j < v.Dims()[1]; ++j)
      for (int i = 0; i < v.Dims()[0]; ++i) {
        const Vec3 p{v.Origin()[0] + i * v.Spacing(), v.Origin()[1] + j * v.Spacing(),
                     v.Origin()[2] + k * v.Spacing()};
        if (Distance(p, t.humeralHeadCentre) <= t.humeralHeadRadiusMm + 2)
          v.SetFill(v.Index(i, j, k), 0);
      }
  const SegmentedBone bone(v);
  EXPECT_THROW(DetectLandmarks(bone), NoGlenoidFound);
  LandmarkOverrides ov;
  ov.facePoint = AddScaled(t.glenoidCentre, t.superiorAxis, 4.0);
  const GlenoidLandmarks L = DetectLandmarks(bone, ov);
  EXPECT_EQ(L.centreSource, "user face point");
  EXPECT_EQ(L.normalSource, "face around the placed point");
  EXPECT_FALSE(L.humeralHeadFound);
  EXPECT_LT(Distance(L.glenoidCentre, t.glenoidCentre), 1.0);
  EXPECT_LT(AngleDeg(L.faceNormal, t.faceNormal), 1.0);
  // With the head in the scan, the click picks the joint found there: the same glenoid.
  const SegmentedBone whole(MakeScapulaVoxmap(ph, 1.0, 3));
  const GlenoidLandmarks J = DetectLandmarks(whole, ov);
  EXPECT_TRUE(J.humeralHeadFound);
  EXPECT_LT(Distance(J.glenoidCentre, L.glenoidCentre), 1.0);
  // A centre placed alone keeps the click and takes the face's normal.
  LandmarkOverrides centre;
  centre.glenoidCentre = ov.facePoint;
  const GlenoidLandmarks C = DetectLandmarks(bone, centre);
  EXPECT_EQ(C.centreSource, "user");
  EXPECT_LT(Distance(C.glenoidCentre, *ov.facePoint), 1e-12);
  EXPECT_LT(AngleDeg(C.faceNormal, t.faceNormal), 2.0);
  // A click in the air is refused by name; the JSON key reads back.
  LandmarkOverrides air;
  air.facePoint = AddScaled(t.glenoidCentre, t.faceNormal, 30.0);
  EXPECT_THROW(DetectLandmarks(bone, air), NoGlenoidFound);
  EXPECT_TRUE(LandmarkOverrides::FromJson({{"face_point_mm", {1, 2, 3}}}).facePoint.has_value());
}

TEST(GlenoidManualPath, TheSideAskedForIsTheOneFound) {
  ScapulaPhantomParams left;
  left.rightSide = false;
  left.glenoidCentreMm[0] = -left.glenoidCentreMm[0];
  const SegmentedBone rightBone(MakeScapulaVoxmap(ScapulaPhantom(ScapulaPhantomParams{}), 1.0, 3));
  const SegmentedBone leftBone(MakeScapulaVoxmap(ScapulaPhantom(left), 1.0, 3));
  DetectionOptions o;
  o.side = ShoulderSide::Right;
  EXPECT_EQ(DetectLandmarks(rightBone, {}, o).side, "right");
  try {
    DetectLandmarks(leftBone, {}, o);
    FAIL() << "a left shoulder was planned as the right";
  } catch (const NoGlenoidFound& e) {
    EXPECT_NE(std::string(e.what()).find("faces the patient's left"), std::string::npos)
        << e.what();
  }
  o.side = ShoulderSide::Left;
  EXPECT_EQ(DetectLandmarks(leftBone, {}, o).side, "left");
}

TEST(GlenoidManualPath, ImplausibleResultsAreFlagged) {
  const ScapulaPhantom ph{ScapulaPhantomParams{}};
  const ScapulaTruth& t = ph.Truth();
  const SegmentedBone bone(MakeScapulaVoxmap(ph, 1.0, 3));
  GlenoidLandmarks L = DetectLandmarks(bone);
  const GlenoidPlan normal = MakeGlenoidPlan(L, MeasureGlenoid(L));
  EXPECT_TRUE(normal.implausible.empty());
  // A face normal turned 40 deg toward anterior: version beyond +-30 deg, correction beyond 15.
  const double a = 40.0 * 3.14159265358979323846 / 180.0;
  L.faceNormal =
      Normalized(Add(Scale(t.lateralAxis, std::cos(a)), Scale(t.anteriorAxis, std::sin(a))));
  const GlenoidPlan odd = MakeGlenoidPlan(L, MeasureGlenoid(L));
  ASSERT_GE(odd.implausible.size(), 2u);
  EXPECT_NE(odd.implausible[0].find("3D version"), std::string::npos);
  EXPECT_EQ(odd.ToJson()["implausible"].size(), odd.implausible.size());
}

TEST(GlenoidManualPath, StepScenesReadTheCTWithThePlansSettings) {
  const ScapulaPhantom ph{ScapulaPhantomParams{}};
  const SegmentedBone bone(MakeScapulaVoxmap(ph, 1.0, 3));
  const GlenoidLandmarks L = DetectLandmarks(bone);
  const GlenoidPlan plan = MakeGlenoidPlan(L, MeasureGlenoid(L));
  const nlohmann::json settings = {{"ct", "/data/chest.vti.mha"}, {"rawThreshold", 150},
                                   {"series", "1.2.3"},           {"exclude", {{1, 2, 3}}},
                                   {"roi", {0, 0, 0, 1, 1, 1}},   {"seed", {9, 9, 9}},
                                   {"resolution", 256},           {"keepAllComponents", true}};
  const nlohmann::json ct = plan.CtBoneJsonWithSettings(settings)["ct"];
  EXPECT_EQ(ct["ct"], "/data/chest.vti.mha");
  EXPECT_EQ(ct["rawThreshold"], 150);
  EXPECT_EQ(ct["series"], "1.2.3");
  EXPECT_EQ(ct["exclude"], settings["exclude"]);
  EXPECT_FALSE(ct.contains("resolution"));
  EXPECT_FALSE(ct.contains("keepAllComponents"));
  EXPECT_NE(ct["roi"], settings["roi"]); // the plan's box around the glenoid
  EXPECT_NEAR(ct["roi"][0].get<double>(), plan.entry[0] - plan.options.roiHalfMm, 1e-9);
  EXPECT_NE(ct["seed"], settings["seed"]);
  EXPECT_THROW(plan.CtBoneJsonWithSettings(nlohmann::json{{"rawThreshold", 1}}),
               std::invalid_argument);
}

TEST(GlenoidManualPath, AToolThatWouldStartInsideBoneIsRefused) {
  // The humeral head 1 mm from the glenoid, sampled at 2 mm: no joint space, one bone. Placed
  // by hand, the glenoid plans, but the reamer's path beyond the face is the head.
  ScapulaPhantomParams touching;
  touching.jointGapMm = 1;
  const ScapulaPhantom ph(touching);
  const ScapulaTruth& t = ph.Truth();
  const SegmentedBone fused(MakeScapulaVoxmap(ph, 2.0, 3));
  ASSERT_EQ(fused.NumBones(), 1);
  LandmarkOverrides ov;
  ov.glenoidCentre = t.glenoidCentre;
  ov.faceNormal = t.faceNormal;
  const GlenoidLandmarks L = DetectLandmarks(fused, ov);
  const GlenoidPlan plan = MakeGlenoidPlan(L, MeasureGlenoid(L));
  try {
    CheckToolStartsOutsideBone(fused, L, plan);
    FAIL() << "a reamer starting inside the humeral head was accepted";
  } catch (const PlanBlocked& e) {
    EXPECT_NE(std::string(e.what()).find("start inside bone"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--exclude"), std::string::npos) << e.what();
  }
  // With the joint space the path is clear.
  const SegmentedBone apart(MakeScapulaVoxmap(ScapulaPhantom(ScapulaPhantomParams{}), 1.0, 3));
  const GlenoidLandmarks La = DetectLandmarks(apart);
  EXPECT_NO_THROW(CheckToolStartsOutsideBone(apart, La, MakeGlenoidPlan(La, MeasureGlenoid(La))));
}
