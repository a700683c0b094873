// The scapula phantom's analytic truth: the set version and inclination come back exactly, the
// native glenoid's rim plane is the face's, and the tissues sit where the header says.
#include "bmGlenoidGeometry.h"
#include "bmScapulaPhantom.h"
#include "bmScapulaVoxmap.h"

#include <gtest/gtest.h>

using namespace bm;

TEST(ScapulaPhantom, TruthHasTheSetAngles) {
  for (double v : {-12.0, -25.0, 5.0})
    for (double i : {8.0, -5.0}) {
      ScapulaPhantomParams p;
      p.versionDeg = v;
      p.inclinationDeg = i;
      const ScapulaPhantom ph(p);
      const ScapulaTruth& t = ph.Truth();
      EXPECT_NEAR(t.version3DDeg, v, 1e-6);
      EXPECT_NEAR(t.inclinationDeg, i, 1e-6);
      EXPECT_NEAR(Distance(t.glenoidCentre, p.glenoidCentreMm), 0.0, 1e-6);
      EXPECT_NEAR(AngleDeg(t.faceNormal, ph.N()), 0.0, 1e-6);
      EXPECT_NEAR(t.glenoidHeightMm, 40.0, 1e-3);
      EXPECT_NEAR(t.glenoidWidthMm, 29.0, 1e-3);
      // Friedman 2D differs from the 3D version only by the glenoid line midpoint's offset from
      // the scapular axis (the upright scapula's axial plane is its transverse plane).
      EXPECT_NEAR(t.friedmanVersionDeg, v, 1.0);
    }
}

TEST(ScapulaPhantom, TissuesAndParts) {
  const ScapulaPhantom ph;
  const auto& t = ph.Truth();
  ScapulaPhantom::Part part;
  // 1 mm under the face centre: the cortical shell; 5 mm: cancellous bone.
  EXPECT_EQ(ph.TissueAt(AddScaled(t.glenoidCentre, t.faceNormal, -1.0), &part),
            ScapulaPhantom::Tissue::Cortical);
  EXPECT_EQ(part, ScapulaPhantom::Part::Scapula);
  EXPECT_EQ(ph.TissueAt(AddScaled(t.glenoidCentre, t.faceNormal, -5.0)),
            ScapulaPhantom::Tissue::Cancellous);
  // The joint space (4 mm at the centre) is soft tissue, then the humeral head.
  EXPECT_EQ(ph.TissueAt(AddScaled(t.glenoidCentre, t.faceNormal, 2.0), &part),
            ScapulaPhantom::Tissue::Soft);
  EXPECT_EQ(ph.TissueAt(AddScaled(t.glenoidCentre, t.faceNormal, 4.5), &part),
            ScapulaPhantom::Tissue::Cortical);
  EXPECT_EQ(part, ScapulaPhantom::Part::HumeralHead);
  EXPECT_EQ(ph.HU(AddScaled(t.glenoidCentre, t.faceNormal, 10.0)), 300.0f);
  // The blade: bone at the trigonum's inner side, soft tissue 4 mm off the scapular plane.
  EXPECT_NE(ph.TissueAt(AddScaled(t.trigonum, t.lateralAxis, 1.0)), ScapulaPhantom::Tissue::Soft);
  EXPECT_EQ(ph.TissueAt(AddScaled(AddScaled(t.trigonum, t.lateralAxis, 10.0), t.anteriorAxis, 4)),
            ScapulaPhantom::Tissue::Soft);
  EXPECT_NE(ph.TissueAt(AddScaled(t.inferiorAngle, Sub(t.glenoidCentre, t.inferiorAngle), 0.02)),
            ScapulaPhantom::Tissue::Soft);
}

TEST(ScapulaPhantom, B2WearLowersThePosteriorRim) {
  const ScapulaPhantom native, b2(ScapulaPhantomParams::B2());
  // Posterior rim (v = -b, u = 0): 35 - sqrt(35^2 - 14.5^2) = 3.14 mm native, 33 - sqrt(35^2 -
  // 2.5^2) = -1.91 mm worn; the anterior rim is untouched.
  EXPECT_NEAR(native.FaceHeight(0, -14.5), 35 - std::sqrt(35 * 35 - 14.5 * 14.5), 1e-9);
  EXPECT_NEAR(b2.FaceHeight(0, -14.5), 33 - std::sqrt(35 * 35 - 2.5 * 2.5), 1e-9);
  EXPECT_NEAR(b2.FaceHeight(0, 14.5), native.FaceHeight(0, 14.5), 1e-12);
  // The worn face turns posteriorly: more retroversion than the native -12 deg.
  EXPECT_LT(b2.Truth().version3DDeg, -14.0);
  EXPECT_LT(b2.Truth().friedmanVersionDeg, -14.0);
}

TEST(ScapulaPhantom, BadParametersAreRefused) {
  ScapulaPhantomParams p;
  p.versionDeg = 60;
  EXPECT_THROW(ScapulaPhantom{p}, std::invalid_argument);
  p = {};
  p.jointGapMm = 0;
  EXPECT_THROW(ScapulaPhantom{p}, std::invalid_argument);
  p = {};
  p.glenoidWidthMm = 50;
  EXPECT_THROW(ScapulaPhantom{p}, std::invalid_argument);
}

TEST(ScapulaPhantom, VoxmapHoldsTheBoneVolume) {
  // Two bones; their voxmap volume against a fine Monte-Carlo-free count: the 2 mm voxmap and
  // the 1 mm voxmap agree within 2 %.
  const ScapulaPhantom ph;
  const Voxmap a = MakeScapulaVoxmap(ph, 2.0, 4), b = MakeScapulaVoxmap(ph, 1.0, 2);
  auto volume = [](const Voxmap& v) {
    double s = 0;
    for (int k = 0; k < v.Dims()[2]; ++k)
      for (int j = 0; j < v.Dims()[1]; ++j)
        for (int i = 0; i < v.Dims()[0]; ++i)
          s += v.Fraction(v.Index(i, j, k));
    return s * v.VoxelVolume();
  };
  const double va = volume(a), vb = volume(b);
  // Humeral head 4/3 pi 22^3 = 44602 mm^3 plus the scapula (blade ~48 cm^3, vault ~23 cm^3).
  EXPECT_GT(vb, 44602 + 60000);
  EXPECT_LT(vb, 44602 + 90000);
  EXPECT_NEAR(va / vb, 1.0, 0.02);
}
