// The clinical path through CT import: the scapula phantom as a CT (partial volume, 10 HU noise)
// segmented by bmImport, then detected and measured against the truth; and Debian's real head
// CT, which holds no shoulder, where detection must refuse rather than invent a glenoid.
#ifdef BM_PLANNING_WITH_IO
#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmImport.h"
#include "bmScapulaCT.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>

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

// The same phantom scanned with 15 deg of gantry tilt and written as DICOM: slice positions move
// along the table, not along the slices' normal. Read as stacked along the normal, the glenoid
// centre moved 33 mm, the version 4 deg and the inclination 7 deg; resampled onto a grid along the
// normal (bmTiltedStack.h), the plan measures the bone where it is.
TEST(PlanningFromCT, GantryTiltedPhantomSeriesThroughImport) {
  ScapulaPhantomParams p;
  p.versionDeg = -18;
  p.inclinationDeg = 10;
  const ScapulaPhantom ph(p);
  const double tilt = 15 * M_PI / 180, sp = 1.0, step = 1.0;
  const Vec3 row{1, 0, 0}, column{0, std::cos(tilt), std::sin(tilt)};
  Vec3 lo, hi;
  ph.Bounds(lo, hi);
  for (int a = 0; a < 3; ++a)
    lo[a] -= 5, hi[a] += 5;
  // Slice k holds the plane through (0, 0, z0 + k step) spanned by row and column; enough rows
  // and slices that the tilted planes cover the bone's box.
  const double height = (hi[1] - lo[1]) / std::cos(tilt);
  const size_t n[3] = {size_t(std::ceil((hi[0] - lo[0]) / sp)), size_t(std::ceil(height / sp)),
                       size_t(std::ceil((hi[2] - lo[2] + height * std::sin(tilt)) / step))};
  const Vec3 origin{lo[0], lo[1], lo[2] - height * std::sin(tilt)};
  CTImage ct;
  ct.hu = HUImage::New();
  HUImage::RegionType region;
  region.SetSize({{n[0], n[1], n[2]}});
  ct.hu->SetRegions(region);
  HUImage::SpacingType spacing;
  spacing[0] = spacing[1] = sp;
  spacing[2] = step;
  ct.hu->SetSpacing(spacing);
  HUImage::DirectionType d;
  HUImage::PointType o;
  for (int a = 0; a < 3; ++a) {
    d[a][0] = row[a];
    d[a][1] = column[a];
    d[a][2] = a == 2 ? 1.0 : 0.0; // the table moves along z
    o[a] = origin[a];
  }
  ct.hu->SetDirection(d);
  ct.hu->SetOrigin(o);
  ct.hu->Allocate();
  float* v = ct.hu->GetBufferPointer();
  for (size_t k = 0; k < n[2]; ++k)
    for (size_t j = 0; j < n[1]; ++j)
      for (size_t i = 0; i < n[0]; ++i) {
        Vec3 c;
        for (int a = 0; a < 3; ++a)
          c[a] = origin[a] + double(i) * sp * row[a] + double(j) * sp * column[a] +
                 (a == 2 ? double(k) * step : 0.0);
        v[i + n[0] * (j + n[1] * k)] = ScapulaVoxelHU(ph, c, {sp, sp, step}, 3);
      }
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("bm-tilted-scapula-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  WriteDicomSeries(ct, dir.string());
  ImportOptions io;
  io.segmentation.keepAllComponents = true;
  io.resolution = 180;
  const ImportResult r = ImportVoxmap(dir.string(), io);
  std::filesystem::remove_all(dir);
  const SegmentedBone bone(r.voxmap);
  const GlenoidLandmarks L = DetectLandmarks(bone);
  const GlenoidMeasurements m = MeasureGlenoid(L);
  const ScapulaTruth& t = ph.Truth();
  std::cout << "[tilted 15 deg] glenoid centre " << Distance(L.glenoidCentre, t.glenoidCentre)
            << " mm from the truth, version " << m.version3DDeg << " deg (truth " << t.version3DDeg
            << "), inclination " << m.inclinationDeg << " deg (truth " << t.inclinationDeg << ")\n";
  EXPECT_LT(Distance(L.glenoidCentre, t.glenoidCentre), 1.0);
  EXPECT_NEAR(m.version3DDeg, t.version3DDeg, 1.0);
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
    // Where each rejected pair lies, in the message's order, for the failure's picture.
    const std::string what = e.what();
    size_t named = 0;
    for (size_t at = what.find(") mm: "); at != std::string::npos; at = what.find(") mm: ", at + 1))
      ++named; // "bone L facing bone M at (x, y, z) mm: why"
    EXPECT_GT(named, 0u);
    EXPECT_EQ(e.rejectedAt.size(), named);
    for (const Vec3& p : e.rejectedAt)
      EXPECT_NE(bone.LabelAt(p) + 1, 0); // finite, inside or beside the scan
  }
}
#endif
