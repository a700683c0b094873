// The trigonum as the root of the scapular spine (bmScapularSpine.h): found in the scapula's own
// frame, it stays on the truth when the patient is turned in the scanner, where the medial tip on
// the axial plane slides along the medial border; without a spine there is no root and the
// landmarks say which trigonum they used.
#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmScapulaPhantom.h"
#include "bmScapulaVoxmap.h"
#include "bmScapularSpine.h"

#include <gtest/gtest.h>

#include <string>

using namespace bm;

namespace {

ScapulaPhantomParams WithSpine(const Vec3& rotationDeg) {
  ScapulaPhantomParams p;
  p.spine = true;
  p.patientRotationDeg = rotationDeg;
  return p;
}

} // namespace

TEST(ScapularSpine, ThePhantomsSpineStandsBehindTheBlade) {
  const ScapulaPhantom with(WithSpine({0, 0, 0})), without;
  const ScapulaTruth& t = with.Truth();
  // 10 mm lateral of the root along the spine's line, 6 mm behind the blade's mid-plane.
  const Vec3 behind = AddScaled(AddScaled(t.trigonum, t.lateralAxis, 10.0), t.anteriorAxis, -6.0);
  EXPECT_NE(with.TissueAt(behind), ScapulaPhantom::Tissue::Soft);
  EXPECT_EQ(without.TissueAt(behind), ScapulaPhantom::Tissue::Soft);
  // Nothing in front of the blade, nor medial of the border.
  EXPECT_EQ(with.TissueAt(AddScaled(t.trigonum, t.anteriorAxis, 6.0)),
            ScapulaPhantom::Tissue::Soft);
  EXPECT_EQ(
      with.TissueAt(AddScaled(AddScaled(t.trigonum, t.lateralAxis, -3.0), t.anteriorAxis, -5.0)),
      ScapulaPhantom::Tissue::Soft);
}

class SpineRootOnATurnedPatient : public ::testing::TestWithParam<Vec3> {};

TEST_P(SpineRootOnATurnedPatient, IsTheTrigonum) {
  const Vec3 r = GetParam();
  SCOPED_TRACE("patient turned " + std::to_string(r[0]) + ", " + std::to_string(r[1]) + ", " +
               std::to_string(r[2]) + " deg about x, y, z");
  const ScapulaPhantom ph(WithSpine(r));
  const ScapulaTruth& t = ph.Truth();
  const SegmentedBone bone(MakeScapulaVoxmap(ph, 1.0, 3));
  const GlenoidLandmarks L = DetectLandmarks(bone);
  EXPECT_EQ(L.trigonumSource, "detected: root of the scapular spine");
  // Within a voxel and a half of the truth (on the mid-plane, at the border).
  EXPECT_LT(Distance(L.trigonum, t.trigonum), 1.5);
  const SpineRootResult s = FindSpineRoot(bone, L.scapulaLabel, L.glenoidCentre);
  ASSERT_TRUE(s.root) << s.reason;
  EXPECT_LT(Dot(s.root->bladeNormal, t.anteriorAxis), -0.99) << "the spine is posterior";
  EXPECT_NEAR(s.root->bladeHalfThicknessMm, ph.Params().bladeThicknessMm / 2, 1.0);
  // The inclination is measured in the scapula's frame: the patient's turn leaves it (the
  // axial-plane trigonum moved it by 3.7-10.8 deg at 10-20 deg about x on a 2.5 mm scan).
  const GlenoidMeasurements m = MeasureGlenoid(L);
  EXPECT_NEAR(m.inclinationDeg, t.inclinationDeg, 1.5);
  EXPECT_NEAR(m.version3DDeg, t.version3DDeg, 1.5);
}

INSTANTIATE_TEST_SUITE_P(AboutEachAxis, SpineRootOnATurnedPatient,
                         ::testing::Values(Vec3{0, 0, 0}, Vec3{20, 0, 0}, Vec3{-20, 0, 0},
                                           Vec3{0, 20, 0}, Vec3{0, -20, 0}, Vec3{15, -15, 20}));

TEST(ScapularSpine, NoSpineNoRootAndTheAxialPlaneSaysSo) {
  const ScapulaPhantom ph;
  const SegmentedBone bone(MakeScapulaVoxmap(ph, 1.0, 3));
  const GlenoidLandmarks L = DetectLandmarks(bone);
  const SpineRootResult s = FindSpineRoot(bone, L.scapulaLabel, L.glenoidCentre);
  EXPECT_FALSE(s.root);
  EXPECT_NE(s.reason.find("no scapular spine"), std::string::npos) << s.reason;
  EXPECT_NE(L.trigonumSource.find("axial plane"), std::string::npos) << L.trigonumSource;
  EXPECT_NE(L.trigonumSource.find("no scapular spine"), std::string::npos) << L.trigonumSource;
  EXPECT_LT(Distance(L.trigonum, ph.Truth().trigonum), 3.0);
}
