// The baseline's octree voxmap (bmOctreeVoxmap.h): it holds exactly the dense voxmap, finds the
// leaf of any voxel, refines to single voxels and removes like Voxmap::Remove.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "bmBoneBlock.h"
#include "bmOctreeVoxmap.h"

namespace {

// A voxmap with uniform regions (air above a bone slab), a spherical hole and random partial fills.
bm::Voxmap Pattern(std::array<int, 3> dims) {
  bm::Voxmap v(dims, 0.05, {0, 0, 0});
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> partial(1, bm::Voxmap::kFull - 1);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        bm::Voxmap::Fill f = k < dims[2] * 2 / 3 ? bm::Voxmap::kFull : 0;
        const double dx = i - dims[0] / 2.0, dy = j - dims[1] / 2.0, dz = k - dims[2] / 3.0;
        if (dx * dx + dy * dy + dz * dz < 25)
          f = 0;
        if ((i * 7 + j * 3 + k) % 97 == 0)
          f = partial(rng);
        v.MutableFill()[v.Index(i, j, k)] = f;
      }
  v.RebuildOccupancy();
  return v;
}

TEST(OctreeVoxmap, CopyToRoundTripsTheDenseVoxmap) {
  for (std::array<int, 3> dims :
       {std::array<int, 3>{32, 32, 32}, {37, 20, 13}, {1, 1, 1}, {64, 64, 19}}) {
    const bm::Voxmap v = Pattern(dims);
    const bm::OctreeVoxmap tree(v);
    bm::Voxmap back(dims, 0.05, {0, 0, 0});
    tree.CopyTo(back);
    EXPECT_TRUE(back == v) << dims[0] << "x" << dims[1] << "x" << dims[2];
    EXPECT_EQ(back.CountBone(), v.CountBone());
    // Brick occupancy is rebuilt too.
    EXPECT_EQ(back.AnyBoneIn({0, 0, 0}, {dims[0] - 1, dims[1] - 1, dims[2] - 1}),
              v.CountBone() > 0);
    std::printf("%dx%dx%d: %d levels, %zu nodes for %lld voxels\n", dims[0], dims[1], dims[2],
                tree.Levels(), tree.NodeCount(), (long long)v.NumVoxels());
    EXPECT_LT(int64_t(tree.NodeCount()), 2 * v.NumVoxels() + 16);
  }
  // Uniform grids collapse to one leaf (the root; the builder leaves one spare node behind).
  const bm::Voxmap full = bm::MakeBoneBlock({1, 1, 1}, 16);
  const bm::OctreeVoxmap solid(full);
  EXPECT_LE(solid.NodeCount(), 2u);
  int level = -1;
  EXPECT_EQ(solid.Value(solid.Find(7, 3, 15, level)), bm::Voxmap::kFull);
  EXPECT_EQ(level, solid.Levels());
}

TEST(OctreeVoxmap, FindRefineAndRemove) {
  const std::array<int, 3> dims{37, 20, 13};
  bm::Voxmap v = Pattern(dims);
  bm::OctreeVoxmap tree(v);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        int level = -1;
        const int32_t leaf = tree.Find(i, j, k, level);
        ASSERT_GE(level, 0);
        ASSERT_LE(level, tree.Levels());
        ASSERT_EQ(tree.Value(leaf), v.GetFill(v.Index(i, j, k)));
      }
  // A voxel deep in the uniform slab sits in a coarse leaf; Refine gives it its own.
  int level = 0;
  tree.Find(2, 2, 1, level);
  EXPECT_GT(level, 0);
  const size_t before = tree.NodeCount();
  const int32_t leaf = tree.Refine(2, 2, 1);
  EXPECT_GT(tree.NodeCount(), before);
  int after = -1;
  EXPECT_EQ(tree.Find(2, 2, 1, after), leaf);
  EXPECT_EQ(after, 0);
  EXPECT_EQ(tree.Refine(2, 2, 1), leaf); // already a voxel leaf: nothing to split
  // Removal as Voxmap::Remove: clamped amount, void flag once.
  bool voided = true;
  EXPECT_EQ(tree.Remove(leaf, bm::Voxmap::kFull / 4, voided), bm::Voxmap::kFull / 4);
  EXPECT_FALSE(voided);
  EXPECT_EQ(tree.Remove(leaf, bm::Voxmap::kFull, voided),
            bm::Voxmap::kFull - bm::Voxmap::kFull / 4);
  EXPECT_TRUE(voided);
  EXPECT_EQ(tree.Remove(leaf, 10, voided), 0);
  EXPECT_FALSE(voided);
  bool denseVoided = false;
  v.Remove(v.Index(2, 2, 1), bm::Voxmap::kFull / 4, denseVoided);
  v.Remove(v.Index(2, 2, 1), bm::Voxmap::kFull, denseVoided);
  v.Remove(v.Index(2, 2, 1), 10, denseVoided);
  // Neighbours in the split leaf keep their value; the copy equals the dense voxmap cut alike.
  bm::Voxmap back(dims, 0.05, {0, 0, 0});
  tree.CopyTo(back);
  EXPECT_TRUE(back == v);
  EXPECT_EQ(back.CountBone(), v.CountBone());
}

} // namespace
