// A scene's bone description (JSON) becomes a voxmap: phantom, CT with ROI/seed, saved voxmap.
#include "bmIOTestUtil.h"

#include "bmImport.h"
#include "bmVoxmapFile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

using namespace bmtest;

TEST(SceneBone, PhantomCtAndVoxmapSources) {
  ScratchDir d("scene");
  nlohmann::json block = {{"phantom", "block"}, {"resolution", 48}};
  bm::Voxmap a = bm::VoxmapFromScene(block, d.path.string());
  EXPECT_NEAR(a.BoneVolume(), bm::GetPhantomInfo("block").boneVolumeMm3, 0.03 * 144.0);
  EXPECT_EQ(std::max({a.Dims()[0], a.Dims()[1], a.Dims()[2]}), 48);

  bm::SaveVoxmap(a, (d / "block.nrrd").string());
  bm::Voxmap b = bm::VoxmapFromScene({{"voxmap", "block.nrrd"}}, d.path.string());
  EXPECT_TRUE(a == b);

  WriteBlock(d / "ct");
  nlohmann::json ct = {{"ct", "ct"},
                       {"resolution", 40},
                       {"threshold", 500},
                       {"seed", {0.0, 0.0, -2.0}},
                       {"roi", {-4, -4, -5, 4, 4, 1}}};
  bm::Voxmap c = bm::VoxmapFromScene(ct, d.path.string());
  EXPECT_NEAR(c.Spacing(), 8.0 / 40, 1e-12);
  EXPECT_NEAR(c.Bounds().lo[0], -4.0, 1e-9);
  EXPECT_NEAR(c.BoneVolume(), 144.0, 0.05 * 144.0);

  EXPECT_THROW(bm::VoxmapFromScene({{"ct", "ct"}, {"phantom", "block"}}, ""), std::runtime_error);
  EXPECT_THROW(bm::VoxmapFromScene({{"phantom", "block"}, {"resolution", "high"}}, ""),
               std::runtime_error);
  EXPECT_THROW(bm::VoxmapFromScene({{"phantom", "block"}, {"seed", {1, 2}}}, ""),
               std::runtime_error);
}

TEST(SceneBone, SkullVaultRegion) {
  // The skull burring scene's bone: the vault of the invesalius head CT around its top
  // (x 122.5, y 105, z 154.5 mm), cropped to a 40 x 40 x 35 mm box.
  const char* cranium = "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
  if (!fs::exists(cranium))
    GTEST_SKIP() << "invesalius-examples is not installed";
  nlohmann::json bone = {
      {"ct", cranium}, {"resolution", 128}, {"roi", {102.5, 85, 125, 142.5, 125, 160}}};
  bm::Voxmap v = bm::VoxmapFromScene(bone, "");
  // A vault of 4-10 mm over a 40 x 40 mm patch: some 5-20 cm^3 of bone.
  EXPECT_GT(v.BoneVolume(), 5000.0);
  EXPECT_LT(v.BoneVolume(), 20000.0);
  std::array<int, 3> ijk;
  ASSERT_TRUE(v.VoxelAt({122.5, 105, 150}, ijk)); // inside the vault, 4.5 mm below its top
  EXPECT_GT(v.GetFill(v.Index(ijk[0], ijk[1], ijk[2])), 0);
  ASSERT_TRUE(v.VoxelAt({122.5, 105, 158}, ijk)); // above it: air
  EXPECT_EQ(v.GetFill(v.Index(ijk[0], ijk[1], ijk[2])), 0);
}

TEST(SceneBone, NoFinerThanTheCTsSpacing) {
  // The glenoid phantom's CT has 0.5 mm pixels and 0.625 mm slices: asked for 192 cells (0.21 mm
  // voxels), a session's import stops at the cells whose voxel is no finer than 0.5 mm.
  bm::ImportOptions opt;
  opt.resolution = 192;
  opt.noFinerThanCT = true;
  const bm::ImportResult r = bm::ImportVoxmap(bm::MakePhantomCT("glenoid"), opt);
  ASSERT_DOUBLE_EQ(std::min({r.ctSpacing[0], r.ctSpacing[1], r.ctSpacing[2]}), 0.5);
  const double longest =
      std::max({r.roi.hi[0] - r.roi.lo[0], r.roi.hi[1] - r.roi.lo[1], r.roi.hi[2] - r.roi.lo[2]});
  const auto& d = r.voxmap.Dims();
  const int cells = std::max({d[0], d[1], d[2]});
  EXPECT_EQ(cells, bm::CellsNoFinerThan(longest, 0.5));
  EXPECT_GT(cells, 60);
  EXPECT_LT(cells, 100);
  EXPECT_GE(r.voxmap.Spacing(), 0.5 - 1e-12); // no finer than the CT
  EXPECT_LT(longest / (cells + 1), 0.5);      // and no coarser than it needs
  bool noted = false;
  for (const std::string& n : r.notes)
    noted = noted || n.find("no finer than the CT's 0.5 mm spacing") != std::string::npos;
  EXPECT_TRUE(noted);
  // A coarser request is kept; without the option the request is kept too.
  opt.resolution = 48;
  EXPECT_EQ(bm::ImportVoxmap(bm::MakePhantomCT("glenoid"), opt).voxmap.Dims(),
            bm::ImportVoxmap(bm::MakePhantomCT("glenoid"),
                             [] {
                               bm::ImportOptions o;
                               o.resolution = 48;
                               return o;
                             }())
                .voxmap.Dims());
  // A small tool keeps voxels it can cut with (here 0.4 mm) where the CT's are coarser.
  opt.resolution = 192;
  opt.toolVoxelMm = 0.4;
  const bm::ImportResult t = bm::ImportVoxmap(bm::MakePhantomCT("glenoid"), opt);
  const auto& td = t.voxmap.Dims();
  EXPECT_EQ(std::max({td[0], td[1], td[2]}), bm::CellsNoFinerThan(longest, 0.4));
  EXPECT_THROW(bm::VoxmapFromScene({{"phantom", "block"}, {"toolVoxelMm", 0}}, ""),
               std::runtime_error);
  // The scene key, checked by type.
  const bm::Voxmap viaScene = bm::VoxmapFromScene(
      {{"phantom", "glenoid"}, {"resolution", 192}, {"noFinerThanCT", true}}, "");
  EXPECT_EQ(viaScene.Dims(), d);
  EXPECT_THROW(bm::VoxmapFromScene({{"phantom", "block"}, {"noFinerThanCT", "yes"}}, ""),
               std::runtime_error);
  // The rule itself.
  EXPECT_EQ(bm::CellsNoFinerThan(41.25, 0.5), 82);
  EXPECT_EQ(bm::CellsNoFinerThan(41.0, 0.5), 82);
  EXPECT_EQ(bm::CellsNoFinerThan(2.0, 0.5), 8); // at least 8 cells
  EXPECT_EQ(bm::CellsNoFinerThan(10.0, 0.0), 0);
  EXPECT_EQ(bm::CellsNoFinerThan(10.0, std::nan("")), 0);
}
