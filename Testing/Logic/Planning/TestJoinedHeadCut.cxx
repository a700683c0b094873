// A humeral head joined to its glenoid (the joint space bridged, as thick slices fuse it) cut off
// along its sphere in the middle of the joint space (bmJoinedHeadCut.h): detection finds no
// joint before and the glenoid after; the cut is a shell no bone voxel is left in; a block or a
// cylinder of bone, deep but no sphere, is not cut.
#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmJoinedHeadCut.h"
#include "bmScapulaPhantom.h"
#include "bmScapulaVoxmap.h"

#include <gtest/gtest.h>

using namespace bm;

TEST(JoinedHeadCut, TheHeadIsCutOffInTheMiddleOfTheJointAndTheGlenoidFound) {
  const ScapulaPhantom ph;
  const ScapulaTruth& t = ph.Truth();
  Voxmap v = MakeScapulaVoxmap(ph, 1.0, 3);
  BridgeJointSpace(v, ph, 12.0);
  const SegmentedBone bone(v);
  EXPECT_THROW(DetectLandmarks(bone), NoGlenoidFound);
  const LandmarksOnCut found =
      DetectCuttingAJoinedHead(v, bone, [](const SegmentedBone& b) { return DetectLandmarks(b); });
  ASSERT_TRUE(found.cut);
  ASSERT_TRUE(found.bone);
  const HeadCut& cut = *found.cut;
  EXPECT_LT(Distance(cut.head.centreMm, t.humeralHeadCentre), 1.5);
  EXPECT_NEAR(cut.head.radiusMm, t.humeralHeadRadiusMm, 1.0);
  ASSERT_TRUE(cut.head.socketCentreMm);
  EXPECT_NEAR(cut.head.socketRadiusMm, ph.Params().faceRadiusMm, 4.0);
  EXPECT_DOUBLE_EQ(cut.head.shellMm, 2 * v.Spacing());
  EXPECT_GT(cut.fill, 0.85) << "a ball's cap";
  // The shell holds no bone, and it lies between the face and the head on the axis.
  int64_t left = 0;
  for (int k = 0; k < v.Dims()[2]; ++k)
    for (int j = 0; j < v.Dims()[1]; ++j)
      for (int i = 0; i < v.Dims()[0]; ++i) {
        const Vec3 p{v.Origin()[0] + i * v.Spacing(), v.Origin()[1] + j * v.Spacing(),
                     v.Origin()[2] + k * v.Spacing()};
        const double f = cut.head.F(p);
        if (f > 0 && f <= cut.head.shellMm && cut.voxmap.Fraction(cut.voxmap.Index(i, j, k)) > 0)
          ++left;
      }
  EXPECT_EQ(left, 0);
  EXPECT_GT(cut.cutVoxels, 100);
  EXPECT_LE(cut.head.F(AddScaled(t.glenoidCentre, t.faceNormal, 4.0)), 0.0) << "head's surface";
  EXPECT_GT(cut.head.F(t.glenoidCentre), cut.head.shellMm) << "the face is the glenoid's";
  const GlenoidMeasurements m = MeasureGlenoid(found.landmarks);
  EXPECT_LT(Distance(found.landmarks.glenoidCentre, t.glenoidCentre), 1.5);
  EXPECT_NEAR(m.version3DDeg, t.version3DDeg, 1.5);
  EXPECT_NEAR(m.inclinationDeg, t.inclinationDeg, 1.5);
  EXPECT_NE(HeadCutSummary(cut).find("middle of the joint space"), std::string::npos);
}

TEST(JoinedHeadCut, ADeepBlockOrCylinderIsNoHead) {
  // A 40 mm cube (fits a 22 mm sphere to 1.3 mm RMS) and a vertebral body's cylinder (radius
  // 18 mm, 30 mm long): deep enough to be tried, not round enough to be cut.
  for (const bool cylinder : {false, true}) {
    SCOPED_TRACE(cylinder ? "cylinder" : "cube");
    Voxmap v({60, 60, 60}, 1.0, {0, 0, 0});
    for (int k = 10; k < 50; ++k)
      for (int j = 10; j < 50; ++j)
        for (int i = 10; i < 50; ++i) {
          const double x = i - 29.5, y = j - 29.5;
          if (!cylinder || (x * x + y * y <= 18.0 * 18.0 && k >= 15 && k < 45))
            v.SetFill(v.Index(i, j, k), Voxmap::kFull);
        }
    const SegmentedBone bone(v);
    const std::vector<HeadCut> cuts = CutJoinedHeads(v, bone);
    EXPECT_TRUE(cuts.empty()) << "a sphere of radius " << cuts.front().head.radiusMm << " mm, RMS "
                              << cuts.front().rmsMm << " mm, coverage " << cuts.front().coverage;
    // What rejects them: the directions where their surface lies on the sphere are rings, which
    // fill little of the cap their mean implies.
    HeadCutOptions any;
    any.minCoverage = 0;
    any.minFill = 0;
    const std::vector<HeadSphere> spheres = FindHeadSpheres(bone, any);
    ASSERT_EQ(spheres.size(), 1u) << "deep and fitted by a sphere: only the fill tells";
    EXPECT_LT(spheres[0].fill, 0.45)
        << "radius " << spheres[0].fit.radiusMm << " mm, RMS " << spheres[0].fit.rmsMm
        << " mm, coverage " << spheres[0].coverage;
    EXPECT_THROW(DetectCuttingAJoinedHead(
                     v, bone, [](const SegmentedBone& b) { return DetectLandmarks(b); }),
                 NoGlenoidFound);
  }
}
