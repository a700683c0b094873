// A scene's bone description (JSON) becomes a voxmap: phantom, CT with ROI/seed, saved voxmap.
#include "bmIOTestUtil.h"

#include "bmImport.h"
#include "bmVoxmapFile.h"

#include <gtest/gtest.h>
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
