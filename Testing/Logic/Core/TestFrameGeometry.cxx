// FrameGeometry (bmFrameGeometry.h): the voxel of an element is the same whether its index is
// formed in 32-bit arithmetic (every index of the grid fits) or in 64-bit arithmetic, and the
// one-element VoxelOf() is VoxelsOf() for that element.
#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

#include "bmFrameGeometry.h"
#include "bmMorton.h"
#include "bmPointShell.h"

namespace {

TEST(FrameGeometry, VoxelIndicesAgreeIn32And64BitArithmetic) {
  const bm::TwistDrill drill;
  const bm::PointShell shell = bm::PointShell::Build(drill, 128);
  const bm::Voxmap bone({301, 203, 97}, 0.1, {-15.0, -10.0, -4.8});
  bm::FrameInput in;
  in.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  in.position = {0.3, -0.1, 0.2};
  bm::FrameGeometry G(in, shell, bone);
  ASSERT_TRUE(G.index32);

  std::mt19937 rng(3);
  constexpr int n = 4096;
  std::vector<float> x(n), y(n), z(n);
  for (int q = 0; q < n; ++q) {
    x[q] = float(rng() % 160);
    y[q] = float(rng() % 160);
    z[q] = float(rng() % 160);
  }
  std::vector<int64_t> idx32(n), idx64(n);
  std::vector<int32_t> brick32(n), brick64(n);
  G.VoxelsOf(x.data(), y.data(), z.data(), n, idx32.data(), brick32.data());
  G.index32 = false;
  G.VoxelsOf(x.data(), y.data(), z.data(), n, idx64.data(), brick64.data());
  int inside = 0;
  for (int q = 0; q < n; ++q) {
    ASSERT_EQ(idx32[q], idx64[q]) << "element " << q;
    ASSERT_EQ(brick32[q], brick64[q]) << "element " << q;
    inside += idx32[q] >= 0;
    if (idx32[q] >= 0) {
      const auto v = bone.Coords(idx32[q]);
      EXPECT_EQ(brick32[q], bone.BrickIndex(v[0] / 8, v[1] / 8, v[2] / 8));
    }
    const std::array<uint32_t, 3> ijk{uint32_t(x[q]), uint32_t(y[q]), uint32_t(z[q])};
    EXPECT_EQ(G.VoxelOf(ijk), idx32[q]);
  }
  EXPECT_GT(inside, n / 10); // both in-grid and outside elements were tested
  EXPECT_LT(inside, n);
}

} // namespace
