// The clinical path through CT import: the scapula phantom as a CT (partial volume, 10 HU noise)
// segmented by bmImport, then detected and measured against the truth; and Debian's real head
// CT, which holds no shoulder, where detection must refuse rather than invent a glenoid.
#ifdef BM_PLANNING_WITH_IO
#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmImport.h"
#include "bmScapulaCT.h"

#include <filesystem>

#include <gtest/gtest.h>

using namespace bm;

TEST(PlanningFromCT, PhantomCTThroughImport) {
  ScapulaPhantomParams p;
  p.versionDeg = -18;
  p.inclinationDeg = 10;
  const ScapulaPhantom ph(p);
  PhantomCTOptions o = ScapulaCTDefaults();
  o.inPlaneSpacingMm = 1.0;
  o.supersample = 3;
  ImportOptions io;
  io.segmentation.keepAllComponents = true;
  io.resolution = 180; // ~1 mm cells over the phantom's ~175 mm
  const ImportResult r = ImportVoxmap(MakeScapulaCT(ph, o), io);
  const SegmentedBone bone(r.voxmap);
  const GlenoidLandmarks L = DetectLandmarks(bone);
  const GlenoidMeasurements m = MeasureGlenoid(L);
  const ScapulaTruth& t = ph.Truth();
  EXPECT_LT(Distance(L.glenoidCentre, t.glenoidCentre), 1.0);
  EXPECT_NEAR(m.version3DDeg, t.version3DDeg, 1.0);
  EXPECT_NEAR(m.friedmanVersionDeg, t.friedmanVersionDeg, 1.0);
  EXPECT_NEAR(m.inclinationDeg, t.inclinationDeg, 1.0);
}

TEST(PlanningFromCT, HeadCTHasNoGlenoid) {
  const char* cranium = "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
  if (!std::filesystem::exists(cranium))
    GTEST_SKIP() << "invesalius-examples is not installed";
  ImportOptions io;
  io.segmentation.keepAllComponents = true;
  io.resolution = 160;
  const ImportResult r = ImportVoxmap(cranium, io);
  const SegmentedBone bone(r.voxmap);
  try {
    const GlenoidLandmarks L = DetectLandmarks(bone);
    FAIL() << "a glenoid was found on a head CT at (" << L.glenoidCentre[0] << ", "
           << L.glenoidCentre[1] << ", " << L.glenoidCentre[2] << ")";
  } catch (const NoGlenoidFound& e) {
    EXPECT_NE(std::string(e.what()).find("no glenoid found"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("place the landmarks"), std::string::npos) << e.what();
  }
}
#endif
