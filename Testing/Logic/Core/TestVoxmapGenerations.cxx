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
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        v.SetFill(v.Index(i, j, k), bm::Voxmap::kFull);
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
  // bricks whose generation moved (marking them seen before reading its rows with LoadFillRow,
  // relaxed atomic loads). When the cutter stops, one
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
          // Rows of the brick with LoadFillRow (as the live view reads them).
          for (int k = bk * 8; k < std::min(bk * 8 + 8, 24); ++k)
            for (int j = bj * 8; j < std::min(bj * 8 + 8, 24); ++j) {
              const int64_t row = v.Index(bi * 8, j, k);
              v.LoadFillRow(row, std::min(8, 40 - bi * 8), copy.data() + row);
            }
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

namespace {

/// Random removal requests (voxel, units), in runs of neighbouring voxels as a pass makes them.
std::vector<bm::Voxmap::RemovalRequest> RandomRequests(const bm::Voxmap& v, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int64_t> voxel(0, v.NumVoxels() - 4);
  std::uniform_int_distribution<int> amount(1, bm::Voxmap::kFull / 3), run(1, 4);
  std::vector<bm::Voxmap::RemovalRequest> r;
  while (int(r.size()) < n) {
    const int64_t at = voxel(rng);
    for (int q = run(rng); q > 0; --q)
      r.push_back({at + q - 1, amount(rng), int32_t(v.BrickOfVoxel(at + q - 1))});
  }
  return r;
}

} // namespace

TEST(VoxmapRemoveOwned, SameFillsTotalsOccupancyAndGenerationsAsRemove) {
  // Two owners (Voxmap::LineOwner with two parts) on two threads at once, against Remove() on
  // every request in order on one: fills, removed units, voided voxels, brick counts, and the
  // bricks that moved must all be equal.
  bm::Voxmap a = FullBlock({40, 24, 24}), b = a;
  SeeAll(a);
  SeeAll(b);
  const auto req = RandomRequests(a, 60000, 11);
  int64_t fillA = 0, voxA = 0;
  for (const auto& r : req) {
    bool voided = false;
    fillA += a.Remove(r.voxel, r.units, voided);
    voxA += voided;
  }
  std::vector<bm::Voxmap::RemovalRequest> parts[2];
  for (const auto& r : req)
    parts[bm::Voxmap::LineOwner(r.voxel, 1)].push_back(r);
  ASSERT_FALSE(parts[0].empty());
  ASSERT_FALSE(parts[1].empty());
  bm::Voxmap::RemovalTotals totals[2];
  std::vector<std::thread> owners;
  for (int p = 0; p < 2; ++p)
    owners.emplace_back([&, p] {
      std::vector<int64_t> touched;
      // In two batches, as the engine hands over one pass task's list after another.
      const size_t half = parts[p].size() / 2;
      const auto t1 = b.RemoveOwned(parts[p].data(), half, touched);
      const auto t2 = b.RemoveOwned(parts[p].data() + half, parts[p].size() - half, touched);
      b.MarkBricksChanged(touched);
      totals[p] = {t1.fill + t2.fill, t1.voxels + t2.voxels};
    });
  for (auto& t : owners)
    t.join();
  EXPECT_EQ(fillA, totals[0].fill + totals[1].fill);
  EXPECT_EQ(voxA, totals[0].voxels + totals[1].voxels);
  EXPECT_GT(voxA, 0);
  for (int64_t i = 0; i < a.NumVoxels(); ++i)
    ASSERT_EQ(a.GetFill(i), b.GetFill(i)) << "voxel " << i;
  const int64_t bricks = int64_t(a.BrickDims()[0]) * a.BrickDims()[1] * a.BrickDims()[2];
  for (int64_t k = 0; k < bricks; ++k) {
    EXPECT_EQ(a.BrickCount(k), b.BrickCount(k)) << "brick " << k;
    EXPECT_EQ(a.BrickGeneration(k), b.BrickGeneration(k)) << "brick " << k;
  }
}

TEST(VoxmapRemoveOwned, OwnersNeverShareACacheLine) {
  bm::Voxmap v({64, 8, 8}, 0.1, {0, 0, 0});
  ASSERT_EQ(reinterpret_cast<uintptr_t>(v.FillData()) % 64, 0u);
  for (int64_t i = 0; i < v.NumVoxels(); ++i) {
    const auto line = (reinterpret_cast<uintptr_t>(v.FillData() + i)) / 64;
    const auto first = (reinterpret_cast<uintptr_t>(v.FillData() + i - i % 16)) / 64;
    ASSERT_EQ(line, first);
    ASSERT_EQ(bm::Voxmap::LineOwner(i, 3), bm::Voxmap::LineOwner(i - i % 16, 3));
  }
  EXPECT_EQ(bm::Voxmap::LineOwner(16, 1), 1);
  EXPECT_EQ(bm::Voxmap::LineOwner(32, 1), 0);
}

TEST(VoxmapRemoveOwned, ReaderOnAnotherThreadMissesNoChange) {
  // As ReaderOnAnotherThreadMissesNoChange above, with the cutter removing through owned
  // batches (plain stores, one fence per batch) instead of a locked decrement per voxel.
  bm::Voxmap v = FullBlock({40, 24, 24});
  std::vector<bm::Voxmap::Fill> copy(size_t(v.NumVoxels()));
  std::vector<uint32_t> seen = SeeAll(v);
  for (int64_t i = 0; i < v.NumVoxels(); ++i)
    copy[size_t(i)] = v.LoadFill(i);
  auto refresh = [&] {
    for (size_t b = 0; b < seen.size(); ++b) {
      const uint32_t g = v.SeenBrickGeneration(int64_t(b));
      if (g == seen[b])
        continue;
      seen[b] = g;
      const int bi = int(b % size_t(v.BrickDims()[0]));
      const int bj = int((b / size_t(v.BrickDims()[0])) % size_t(v.BrickDims()[1]));
      const int bk = int(b / size_t(v.BrickDims()[0] * v.BrickDims()[1]));
      for (int k = bk * 8; k < std::min(bk * 8 + 8, 24); ++k)
        for (int j = bj * 8; j < std::min(bj * 8 + 8, 24); ++j)
          for (int i = bi * 8; i < std::min(bi * 8 + 8, 40); ++i)
            copy[size_t(v.Index(i, j, k))] = v.LoadFill(v.Index(i, j, k));
    }
  };
  std::atomic<bool> stop{false};
  std::thread cutter([&] {
    std::vector<int64_t> touched;
    for (unsigned batch = 0; batch < 400; ++batch) {
      const auto req = RandomRequests(v, 1000, 100 + batch);
      touched.clear();
      v.RemoveOwned(req.data(), req.size(), touched);
      v.MarkBricksChanged(touched);
    }
    stop.store(true);
  });
  while (!stop.load())
    refresh();
  cutter.join();
  refresh();
  for (int64_t i = 0; i < v.NumVoxels(); ++i)
    ASSERT_EQ(std::max(copy[size_t(i)], 0), std::max(v.GetFill(i), 0)) << "voxel " << i;
}

TEST(VoxmapChangeReach, BitsSayWhereInTheirBricksTheChangedVoxelsLay) {
  // Odd sizes (partial bricks on the far faces); each voxel's bit against its coordinates.
  bm::Voxmap v = FullBlock({37, 21, 19});
  const int band = bm::Voxmap::kBrick - bm::Voxmap::kReachBand;
  for (int k = 0; k < 19; ++k)
    for (int j = 0; j < 21; ++j)
      for (int i = 0; i < 37; ++i) {
        const int o = int(i % 8 >= band) | int(j % 8 >= band) << 1 | int(k % 8 >= band) << 2;
        ASSERT_EQ(v.ReachBitOfVoxel(v.Index(i, j, k)), 1 << o) << i << " " << j << " " << k;
      }
  SeeAll(v);
  for (int64_t b = 0; b < int64_t(v.BrickDims()[0]) * v.BrickDims()[1] * v.BrickDims()[2]; ++b)
    v.TakeBrickReach(b);
  const int64_t brick = v.BrickIndex(1, 1, 0);
  EXPECT_EQ(v.TakeBrickReach(brick), 0) << "taken: nothing since";

  // Owned removals record exact bits only once a reader asked for them (before, no bits at all).
  auto removeOwned = [&](int i, int j, int k) {
    std::vector<int64_t> touched;
    const int64_t idx = v.Index(i, j, k);
    const bm::Voxmap::RemovalRequest r{idx, bm::Voxmap::kFull / 8, int32_t(v.BrickOfVoxel(idx))};
    v.RemoveOwned(&r, 1, touched);
    v.MarkBricksChanged(touched);
  };
  removeOwned(9, 10, 1);
  EXPECT_EQ(v.TakeBrickReach(brick), 0) << "not asked for: none recorded (read as all eight)";
  EXPECT_EQ(v.BrickGeneration(brick) & 1u, 1u) << "but the brick is marked changed";
  v.WantBrickReach();
  removeOwned(9, 10, 1);  // local (1, 2, 1): octant 0
  removeOwned(14, 10, 6); // local (6, 2, 6): x and z in the band
  removeOwned(10, 15, 2); // local (2, 7, 2): y
  EXPECT_EQ(v.TakeBrickReach(brick), (1 << 0) | (1 << 5) | (1 << 2));
  EXPECT_EQ(v.TakeBrickReach(brick), 0);
  // Every other write records all eight (Remove, SetFill).
  bool voided = false;
  v.Remove(v.Index(9, 10, 1), 1, voided);
  EXPECT_EQ(v.TakeBrickReach(brick), bm::Voxmap::kReachAll);
  v.SetFill(v.Index(9, 10, 1), 5);
  EXPECT_EQ(v.TakeBrickReach(brick), bm::Voxmap::kReachAll);
  // A removal from a void voxel changes nothing: no bits, no generation.
  v.SetFill(v.Index(9, 10, 1), 0);
  const uint32_t g = v.SeenBrickGeneration(brick);
  v.TakeBrickReach(brick);
  removeOwned(9, 10, 1);
  EXPECT_EQ(v.TakeBrickReach(brick), 0);
  EXPECT_EQ(v.SeenBrickGeneration(brick), g);
}
