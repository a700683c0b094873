// The clinical path through CT import: the scapula phantom as a CT (partial volume, 10 HU noise)
// segmented by bmImport, then detected and measured against the truth; and Debian's real head
// CT, which holds no shoulder, where detection must refuse rather than invent a glenoid.
#ifdef BM_PLANNING_WITH_IO
#include "bmGlenoidLandmarks.h"
#include "bmGlenoidMeasurements.h"
#include "bmImport.h"
#include "bmJoinedHeadCut.h"
#include "bmScapulaCT.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
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
// A humeral head joined to its glenoid at the threshold (1 mm joint space, 2.5 mm slices): no
// joint is found; the head cut off along its sphere, in the middle of the joint space to its
// socket, gives the glenoid back within 2 mm and 2 deg; a step's bone that leaves the head out
// keeps no bone in front of the face and none of the head.
TEST(PlanningFromCT, AJoinedHumeralHeadIsCutOffAndLeftOutOfTheStepsBone) {
  ScapulaPhantomParams p;
  p.jointGapMm = 1;
  p.spine = true;
  const ScapulaPhantom ph(p);
  const ScapulaTruth& t = ph.Truth();
  PhantomCTOptions o = ScapulaCTDefaults();
  o.inPlaneSpacingMm = 1.4;
  o.sliceSpacingMm = 2.5;
  ImportOptions io;
  io.segmentation.keepAllComponents = true;
  io.resolution = 180;
  const CTImage ct = MakeScapulaCT(ph, o);
  const ImportResult r = ImportVoxmap(ct, io);
  const SegmentedBone bone(r.voxmap);
  EXPECT_THROW(DetectLandmarks(bone), NoGlenoidFound) << "the joint is resolved: no test";
  HeadCutOptions hc;
  hc.scanSpacingMm = 2.5;
  const std::vector<HeadCut> cuts = CutJoinedHeads(r.voxmap, bone, hc);
  ASSERT_FALSE(cuts.empty());
  const HeadCut& cut = cuts.front();
  EXPECT_LT(Distance(cut.head.centreMm, t.humeralHeadCentre), 1.5);
  EXPECT_NEAR(cut.head.radiusMm, t.humeralHeadRadiusMm, 1.5);
  ASSERT_TRUE(cut.head.socketCentreMm) << "the face beside the fused disc gives the socket";
  EXPECT_NEAR(cut.head.socketRadiusMm, p.faceRadiusMm, 5.0);
  EXPECT_GT(cut.cutVoxels, 0);
  const GlenoidLandmarks L = DetectLandmarks(SegmentedBone(cut.voxmap));
  const GlenoidMeasurements m = MeasureGlenoid(L);
  EXPECT_LT(Distance(L.glenoidCentre, t.glenoidCentre), 2.0);
  EXPECT_NEAR(m.version3DDeg, t.version3DDeg, 2.0);
  EXPECT_NEAR(m.inclinationDeg, t.inclinationDeg, 2.0);

  // The step's bone: the scapula at a seed in the vault, the head left out (its JSON round trip).
  ImportOptions step;
  step.segmentation.seedMm = AddScaled(t.glenoidCentre, t.faceNormal, -10.0);
  step.segmentation.excludeHeads.push_back(cut.head);
  step.resolution = 180;
  const ImportOptions back = ImportOptionsFromJson(ImportOptionsToJson(step));
  ASSERT_EQ(back.segmentation.excludeHeads.size(), 1u);
  EXPECT_EQ(back.segmentation.excludeHeads[0].centreMm, cut.head.centreMm);
  EXPECT_EQ(back.segmentation.excludeHeads[0].socketRadiusMm, cut.head.socketRadiusMm);
  EXPECT_EQ(back.segmentation.excludeHeads[0].shellMm, cut.head.shellMm);
  const ImportResult s = ImportVoxmap(ct, back);
  const Voxmap& v = s.voxmap;
  auto fractionAt = [&](const Vec3& q) {
    const auto& d = v.Dims();
    int ijk[3];
    for (int a = 0; a < 3; ++a) {
      ijk[a] = int(std::lround((q[size_t(a)] - v.Origin()[size_t(a)]) / v.Spacing()));
      if (ijk[a] < 0 || ijk[a] >= d[size_t(a)])
        return 0.0;
    }
    return v.Fraction(v.Index(ijk[0], ijk[1], ijk[2]));
  };
  // Nothing in front of the face along its normal (the joint space and the head)...
  for (double w = 1.0; w <= 2 * t.humeralHeadRadiusMm; w += 0.5)
    EXPECT_LT(fractionAt(AddScaled(t.glenoidCentre, t.faceNormal, w)), 0.5) << w << " mm out";
  // ... the face and the vault behind it kept.
  EXPECT_GT(fractionAt(AddScaled(t.glenoidCentre, t.faceNormal, -3.0)), 0.5);
  bool notes = false;
  for (const auto& n : s.notes)
    notes = notes || n.find("humeral head cut off its glenoid left out") != std::string::npos;
  EXPECT_TRUE(notes) << s.Report();

  // Refusals name the key.
  for (
      const char* bad :
      {R"([{"centre_mm": [0, 0, 0], "radius_mm": 0, "shell_mm": 1}])",
       R"([{"centre_mm": [0, 0, 0], "radius_mm": 20, "shell_mm": 1, "socket_centre_mm": [1, 0, 0], "socket_radius_mm": 10}])",
       R"([{"centre_mm": [0, 0], "radius_mm": 20, "shell_mm": 1}])", R"({"centre_mm": 1})"}) {
    try {
      ImportOptionsFromJson({{"exclude_heads", nlohmann::json::parse(bad)}});
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("exclude_heads"), std::string::npos) << e.what();
    }
  }
}
#endif
