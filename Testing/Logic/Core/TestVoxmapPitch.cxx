// TestVoxmapPitch.cxx - the voxmap's padded rows and slices (bmVoxmap.h, Voxmap::Pitch): which
// grids get them, that indices and coordinates stay inverse and inside the storage, and that an
// engine cutting a padded voxmap gives exactly what it gives on the same bone without padding
// and never writes the padding.
#include <gtest/gtest.h>

#include <set>

#include "bmBoneBlock.h"
#include "bmCpuEngine.h"
#include "bmPointShell.h"
#include "bmTestFeed.h"

namespace {

using Pitch = std::array<int, 2>;

TEST(VoxmapPitch, RowsOfWholeCacheLinesAndSlicesOfWhole4KiBArePadded) {
  EXPECT_EQ(bm::Voxmap::PitchFor({1024, 1024, 307}), (Pitch{1040, 1025}));
  EXPECT_EQ(bm::Voxmap::PitchFor({512, 512, 154}), (Pitch{528, 513}));
  EXPECT_EQ(bm::Voxmap::PitchFor({512, 300, 154}), (Pitch{528, 300})); // 528 * 300 % 1024 != 0
  EXPECT_EQ(bm::Voxmap::PitchFor({16, 64, 3}), (Pitch{32, 65}));
  EXPECT_EQ(bm::Voxmap::PitchFor({40, 24, 24}), (Pitch{40, 24})); // rows of 2.5 lines: none
  EXPECT_EQ(bm::Voxmap::PitchFor({37, 21, 19}), (Pitch{37, 21}));
  EXPECT_EQ(bm::Voxmap::PitchFor({1, 1, 20}), (Pitch{1, 1}));
  const bm::Voxmap v({16, 64, 3}, 0.5, {0, 0, 0});
  EXPECT_EQ(v.Pitch(), (Pitch{32, 65}));
  EXPECT_EQ(v.NumVoxels(), 16 * 64 * 3);
  EXPECT_EQ(v.StorageSize(), 32 * 65 * 3);
}

TEST(VoxmapPitch, IndexAndCoordsAreInverseAndInsideTheStorage) {
  for (const std::array<int, 3> dims : {std::array<int, 3>{16, 64, 3}, {48, 32, 5}, {37, 21, 4}}) {
    const bm::Voxmap v(dims, 0.5, {0, 0, 0});
    std::set<int64_t> seen;
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          const int64_t idx = v.Index(i, j, k);
          ASSERT_GE(idx, 0);
          ASSERT_LT(idx, v.StorageSize());
          ASSERT_EQ(v.Coords(idx), (std::array<int, 3>{i, j, k}));
          ASSERT_EQ(v.BrickOfVoxel(idx), v.BrickIndex(i / 8, j / 8, k / 8));
          seen.insert(idx);
        }
    EXPECT_EQ(int64_t(seen.size()), v.NumVoxels());
  }
}

// The drilling block at voxmap 64 (64 x 64 x 19: padded) against the same bone in a grid one
// void column wider (65 x 64 x 19: not padded), voxel centres at the same places: a feed through
// both must give the same frames to the last fixed-point unit and leave the same fills, and the
// padding of the first must stay void.
TEST(VoxmapPitch, ACutOnAPaddedVoxmapEqualsTheCutWithoutPadding) {
  const bm::TwistDrill drill;
  const bm::PointShell shell = bm::PointShell::Build(drill, 256);
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, drill);
  bm::Voxmap padded = bm::MakeBoneBlock({5.0, 5.0, 1.5}, 64);
  const auto d = padded.Dims();
  ASSERT_NE(padded.Pitch()[0], d[0]);
  ASSERT_NE(padded.Pitch()[1], d[1]);
  bm::Voxmap plain({d[0] + 1, d[1], d[2]}, padded.Spacing(), padded.Origin());
  ASSERT_EQ(plain.Pitch(), (Pitch{d[0] + 1, d[1]}));
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        plain.MutableFill()[plain.Index(i, j, k)] = padded.GetFill(padded.Index(i, j, k));
  plain.RebuildOccupancy();

  for (int threads : {1, 2}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    bm::Voxmap a = padded, b = plain;
    bm::CpuEngine ea(a, drill, shell, model, threads), eb(b, drill, shell, model, threads);
    bm::test::Feed feed;
    feed.axis = Eigen::Vector3d(0.3, -0.2, 1.0); // oblique: rows and slices both crossed
    feed.frames = 150;
    const auto ra = bm::test::RunFeed(ea, drill, feed), rb = bm::test::RunFeed(eb, drill, feed);
    ASSERT_GT(ra.back().engagedCutting, 0);
    int64_t removed = 0;
    for (size_t f = 0; f < ra.size(); ++f) {
      ASSERT_EQ(ra[f].thrustFixed, rb[f].thrustFixed) << "frame " << f;
      ASSERT_EQ(ra[f].torqueFixed, rb[f].torqueFixed) << "frame " << f;
      ASSERT_EQ(ra[f].engagedElements, rb[f].engagedElements) << "frame " << f;
      ASSERT_EQ(ra[f].removedFill, rb[f].removedFill) << "frame " << f;
      ASSERT_EQ(ra[f].removedVoxels, rb[f].removedVoxels) << "frame " << f;
      removed += ra[f].removedVoxels;
    }
    EXPECT_GT(removed, 100);
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i)
          ASSERT_EQ(a.GetFill(a.Index(i, j, k)), b.GetFill(b.Index(i, j, k)))
              << "voxel " << i << " " << j << " " << k;
    // Every storage entry that is no grid voxel is padding: still void.
    std::vector<char> grid(size_t(a.StorageSize()), 0);
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i)
          grid[size_t(a.Index(i, j, k))] = 1;
    for (int64_t x = 0; x < a.StorageSize(); ++x)
      if (!grid[size_t(x)]) {
        ASSERT_EQ(a.FillData()[x], 0) << "padding entry " << x;
      }
  }
}

} // namespace
