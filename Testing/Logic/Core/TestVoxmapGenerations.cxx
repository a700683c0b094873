// TestVoxmapGenerations.cxx - the voxmap's per-brick change generations (bmVoxmap.h): a reader
// learns exactly which bricks changed since it last looked, from any thread.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <random>
#include <thread>
#include <vector>

#include "bmVoxmap.h"

namespace {

bm::Voxmap FullBlock(std::array<int, 3> dims) {
  bm::Voxmap v(dims, 0.1, {0, 0, 0});
  for (int64_t i = 0; i < v.NumVoxels(); ++i)
    v.SetFill(i, bm::Voxmap::kFull);
  return v;
}

std::vector<uint32_t> SeeAll(const bm::Voxmap& v) {
  std::vector<uint32_t> g(size_t(v.BrickDims()[0]) * v.BrickDims()[1] * v.BrickDims()[2]);
  for (size_t b = 0; b < g.size(); ++b)
    g[b] = v.SeenBrickGeneration(int64_t(b));
  return g;
}

} // namespace

TEST(VoxmapGenerations, BrickOfVoxelMatchesIntegerDivision) {
  // Odd sizes, so that bricks on the far faces are partial.
  bm::Voxmap v({37, 21, 13}, 0.1, {0, 0, 0});
  for (int k = 0; k < 13; ++k)
    for (int j = 0; j < 21; ++j)
      for (int i = 0; i < 37; ++i)
        ASSERT_EQ(
            v.BrickOfVoxel(v.Index(i, j, k)),
            v.BrickIndex(i / bm::Voxmap::kBrick, j / bm::Voxmap::kBrick, k / bm::Voxmap::kBrick))
            << i << " " << j << " " << k;
  // A one-voxel-wide grid (the reciprocal of 1 does not fit in 64 bits).
  bm::Voxmap thin({1, 1, 20}, 0.1, {0, 0, 0});
  for (int k = 0; k < 20; ++k)
    ASSERT_EQ(thin.BrickOfVoxel(k), k / bm::Voxmap::kBrick);
}

TEST(VoxmapGenerations, ExactlyTheChangedBricksMoveOn) {
  bm::Voxmap v = FullBlock({30, 20, 17});
  std::vector<uint32_t> seen = SeeAll(v);
  // Nothing changed: the same values again.
  EXPECT_EQ(SeeAll(v), seen);

  // Removal from a bone voxel changes its brick only.
  bool voided = false;
  const int64_t idx = v.Index(9, 17, 3);
  const int64_t brick = v.BrickIndex(1, 2, 0);
  v.Remove(idx, bm::Voxmap::kFull / 4, voided);
  EXPECT_EQ(v.BrickGeneration(brick) & 1u, 1u) << "changed and not seen yet: odd";
  std::vector<uint32_t> now = SeeAll(v);
  for (size_t b = 0; b < now.size(); ++b)
    EXPECT_EQ(now[b] != seen[b], int64_t(b) == brick) << "brick " << b;
  EXPECT_EQ(now[size_t(brick)] & 1u, 0u) << "seen: even";

  // Removal from a void voxel changes no fraction, so no generation.
  v.Remove(idx, bm::Voxmap::kFull, voided);
  ASSERT_TRUE(voided);
  seen = SeeAll(v);
  v.Remove(idx, 100, voided);
  EXPECT_EQ(SeeAll(v), seen);

  // SetFill to a new value changes the brick; to the same value it does not.
  v.SetFill(v.Index(29, 0, 16), bm::Voxmap::kFull / 2);
  now = SeeAll(v);
  EXPECT_NE(now[size_t(v.BrickIndex(3, 0, 2))], seen[size_t(v.BrickIndex(3, 0, 2))]);
  v.SetFill(v.Index(29, 0, 16), bm::Voxmap::kFull / 2);
  EXPECT_EQ(SeeAll(v), now);

  // Two readers: each one's values tell it about changes since its own look, whoever looked
  // in between.
  const uint32_t a = v.SeenBrickGeneration(brick);
  v.Remove(v.Index(8, 16, 0), 1, voided);
  const uint32_t b = v.SeenBrickGeneration(brick); // the other reader looks first
  EXPECT_NE(b, a);
  EXPECT_NE(v.SeenBrickGeneration(brick), a) << "the first reader must still see the change";

  // Bulk writes: every brick changed.
  seen = SeeAll(v);
  v.RebuildOccupancy();
  now = SeeAll(v);
  for (size_t q = 0; q < now.size(); ++q)
    EXPECT_NE(now[q], seen[q]);

  // A copy keeps the generations.
  bm::Voxmap c = v;
  EXPECT_EQ(SeeAll(c), now);
}

TEST(VoxmapGenerations, ReaderOnAnotherThreadMissesNoChange) {
  // One thread cuts voxels at random; this thread keeps a copy of the fills, refreshing only the
  // bricks whose generation moved (marking them seen before reading). When the cutter stops, one
  // more pass must make the copy equal to the voxmap (as fractions: removal from a void voxel
  // lowers its fill below 0 but changes nothing a reader shows, and moves no generation).
  bm::Voxmap v = FullBlock({40, 24, 24});
  std::vector<bm::Voxmap::Fill> copy(size_t(v.NumVoxels()));
  std::vector<uint32_t> seen(size_t(v.BrickDims()[0]) * v.BrickDims()[1] * v.BrickDims()[2]);
  auto refresh = [&](bool all) {
    for (int bk = 0; bk < v.BrickDims()[2]; ++bk)
      for (int bj = 0; bj < v.BrickDims()[1]; ++bj)
        for (int bi = 0; bi < v.BrickDims()[0]; ++bi) {
          const int64_t b = v.BrickIndex(bi, bj, bk);
          const uint32_t g = v.SeenBrickGeneration(b);
          if (!all && g == seen[size_t(b)])
            continue;
          seen[size_t(b)] = g;
          for (int k = bk * 8; k < std::min(bk * 8 + 8, 24); ++k)
            for (int j = bj * 8; j < std::min(bj * 8 + 8, 24); ++j)
              for (int i = bi * 8; i < std::min(bi * 8 + 8, 40); ++i)
                copy[size_t(v.Index(i, j, k))] = v.LoadFill(v.Index(i, j, k));
        }
  };
  refresh(true);
  std::atomic<bool> stop{false};
  std::thread cutter([&] {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int64_t> voxel(0, v.NumVoxels() - 1);
    std::uniform_int_distribution<int> amount(1, bm::Voxmap::kFull / 8);
    for (int n = 0; n < 400000; ++n) {
      bool voided = false;
      v.Remove(voxel(rng), amount(rng), voided);
    }
    stop.store(true);
  });
  int passes = 0;
  while (!stop.load()) {
    refresh(false);
    ++passes;
  }
  cutter.join();
  refresh(false);
  for (int64_t i = 0; i < v.NumVoxels(); ++i)
    ASSERT_EQ(std::max(copy[size_t(i)], 0), std::max(v.GetFill(i), 0))
        << "voxel " << i << " after " << passes << " passes";
}
