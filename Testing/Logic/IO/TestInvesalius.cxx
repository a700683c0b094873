// Real CT: Debian's invesalius-examples head CT (Docs/Platform.md section 5) imports, and the
// skull it segments has a plausible volume and extent.
#include "bmIOTestUtil.h"

#include "bmImport.h"
#include "bmInvesaliusReader.h"
#include "bmVoxmapFile.h"

#include <gtest/gtest.h>

using namespace bmtest;

namespace {
const char* kCranium = "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
}

TEST(Invesalius, ReadsTheProjectLayoutFromItsPlist) {
  if (!fs::exists(kCranium))
    GTEST_SKIP() << "invesalius-examples is not installed";
  bm::CTImage ct = bm::ReadCT(kCranium);
  EXPECT_EQ(ct.format, "InVesalius");
  EXPECT_EQ(ct.modality, "CT");
  EXPECT_EQ(ct.Size(), (std::array<int, 3>{256, 256, 108}));
  EXPECT_NEAR(ct.Spacing()[0], 0.9570312, 1e-6);
  EXPECT_NEAR(ct.Spacing()[2], 1.5, 1e-9);
  EXPECT_EQ(ct.huMin, -1024.0f); // true Hounsfield units: air at the scanner's floor
  EXPECT_GT(ct.huMax, 2000.0f);
  EXPECT_TRUE(ct.warnings.empty());
  bm::ReadOptions small;
  small.maxMemoryBytes = 1 << 20;
  EXPECT_THROW(bm::ReadCT(kCranium, small), std::runtime_error);
}

TEST(Invesalius, SkullImports) {
  if (!fs::exists(kCranium))
    GTEST_SKIP() << "invesalius-examples is not installed";
  ScratchDir d("cranium");
  bm::ImportOptions opt;
  opt.resolution = 256; // 0.79 mm voxels, finer than the CT's 0.96 mm: thin bone is kept
  bm::ImportResult r = bm::ImportToFile(kCranium, (d / "skull.nrrd").string(), opt);
  std::cout << r.Report();
  // An adult skull (vault, base, facial bones; the largest connected bone) is a few hundred cm^3;
  // InVesalius' own bone surface of this CT (threshold 226 HU) encloses 658 cm^3.
  EXPECT_GT(r.segmentedVolumeMm3, 350e3);
  EXPECT_LT(r.segmentedVolumeMm3, 900e3);
  // The voxmap keeps the CT's bone surface; plates thinner than half a CT voxel (orbit, ethmoid),
  // about 4 % of this skull's segmented volume, do not survive the sharpening.
  EXPECT_LT(r.voxmap.BoneVolume(), r.segmentedVolumeMm3);
  EXPECT_GT(r.voxmap.BoneVolume(), 0.93 * r.segmentedVolumeMm3);
  // Extent: a head is ~140-160 mm wide and ~170-200 mm long; the scan covers 162 mm axially.
  const double ex = r.roi.hi[0] - r.roi.lo[0], ey = r.roi.hi[1] - r.roi.lo[1],
               ez = r.roi.hi[2] - r.roi.lo[2];
  EXPECT_GT(ex, 120);
  EXPECT_LT(ex, 200);
  EXPECT_GT(ey, 150);
  EXPECT_LT(ey, 230);
  EXPECT_GT(ez, 100);
  EXPECT_LE(ez, 162.5);
  EXPECT_EQ(std::max({r.voxmap.Dims()[0], r.voxmap.Dims()[1], r.voxmap.Dims()[2]}), 256);
  // Cortical and cancellous bone are told apart in the material scale.
  int cortical = 0, softer = 0;
  for (int64_t v = 0; v < r.voxmap.StorageSize(); ++v) // the padding is void: not counted
    if (r.voxmap.GetFill(v) == bm::Voxmap::kFull)
      (r.voxmap.Material(v) >= 0.99f ? cortical : softer)++;
  EXPECT_GT(cortical, 1000);
  EXPECT_GT(softer, 1000);
  bm::Voxmap back = bm::LoadVoxmap((d / "skull.nrrd").string());
  EXPECT_TRUE(back == r.voxmap);
}
