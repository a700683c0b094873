// Kim et al.'s pieces: the tool's signed distance field, the bone surface point shell and its
// flood-fill regeneration, the contact force; and the feed balance of the cutting model.
#include <gtest/gtest.h>

#include <cmath>

#include "bmBoneSurfaceShell.h"
#include "bmFeedBalance.h"
#include "bmKimParkContact.h"
#include "bmSessionTestUtil.h"
#include "bmToolDistanceField.h"

namespace {

TEST(ToolDistanceField, MatchesTheSphereOfABurrWithTrilinearLookup) {
  const bm::ArcLipTool burr(bm::ArcLipTool::Burr(0.5));
  const bm::ToolDistanceField sdf(burr, 128);
  // Below the equator the burr is a sphere of radius 0.5 centred at z = 0.5.
  for (double z : {-0.05, 0.0, 0.1, 0.3}) {
    for (double x : {0.0, 0.2, 0.45}) {
      const Eigen::Vector3d q(x, 0.03, z);
      Eigen::Vector3d g;
      const double d = sdf.Sample(q, g);
      const double exact = (q - Eigen::Vector3d(0, 0, 0.5)).norm() - 0.5;
      EXPECT_NEAR(d, exact, 1.5 * sdf.Spacing()) << x << " " << z;
    }
  }
  Eigen::Vector3d g;
  sdf.Sample({0.0, 0.0, 0.05}, g); // just inside the bottom: the gradient points down and out
  EXPECT_LT(g(2), -0.9);
  EXPECT_EQ(sdf.Sample({10, 0, 0}, g), sdf.Far());
}

TEST(BoneSurfaceShell, PointsOnTheSurfaceRegeneratedByFloodFillAfterRemoval) {
  const bm::Scene scene = bm::test::BurrScene(0.5, {1, 1, 0.5}, 32, 64, 0);
  bm::Voxmap bone = bm::MakeSceneBlock(scene);
  const auto d = bone.Dims();
  bm::BoneSurfaceShell shell(bone);
  // A box of nx x ny x nz voxels has all but its (nx-2)(ny-2)(nz-2) interior voxels on the surface.
  EXPECT_EQ(int64_t(shell.Size()), bone.CountBone() - int64_t(d[0] - 2) * (d[1] - 2) * (d[2] - 2));
  int up = 0;
  shell.ForEachIn({-0.1, -0.1, -0.05}, {0.1, 0.1, 0.0}, [&](const bm::SurfacePoint& p) {
    if (p.position(2) > -0.02)
      up += p.normal(2) > 0.99;
  });
  EXPECT_GT(up, 0);
  // Remove a top-centre voxel (Boolean, as Kim et al. do): the voxel below becomes a surface point.
  const int i = d[0] / 2, j = d[1] / 2, k = d[2] - 1;
  const auto c = bone.GridToWorld({double(i), double(j), double(k)});
  const Eigen::Vector3d centre(c[0], c[1], c[2]);
  int64_t fill = 0;
  const size_t before = shell.Size();
  const int64_t removed = shell.Cut(
      centre - Eigen::Vector3d::Constant(0.01), centre + Eigen::Vector3d::Constant(0.01),
      [&](const Eigen::Vector3d& x) { return (x - centre).norm() < 1e-6; }, fill);
  EXPECT_EQ(removed, 1);
  EXPECT_EQ(fill, bm::Voxmap::kFull);
  // Its point is gone; the 9 voxels under it (26-neighbours, interior so far) are surface now.
  EXPECT_EQ(shell.Size(), before - 1 + 9);
  bool below = false;
  shell.ForEachIn(centre - Eigen::Vector3d::Constant(0.1), centre + Eigen::Vector3d::Constant(0.1),
                  [&](const bm::SurfacePoint& p) {
                    if (p.voxel == bone.Index(i, j, k - 1))
                      below = true;
                  });
  EXPECT_TRUE(below);
  // The engine's way: fill lowered to void elsewhere; Sync finds it.
  bone.SetFill(bone.Index(i + 3, j, k), 0);
  EXPECT_EQ(
      shell.Sync(centre - Eigen::Vector3d::Constant(0.2), centre + Eigen::Vector3d::Constant(0.2)),
      1);
}

TEST(KimParkContact, PenaltyForcePushesOutAndItsJacobianIsTheForcesSlope) {
  const bm::Scene scene = bm::test::BurrScene(0.5, {2, 2, 1}, 64, 64, 0);
  bm::Voxmap bone = bm::MakeSceneBlock(scene);
  const bm::ArcLipTool burr(bm::ArcLipTool::Burr(0.5, 8));
  const bm::ToolDistanceField sdf(burr, 128);
  bm::BoneSurfaceShell shell(bone);
  bm::KimParkContact contact(sdf, shell, 2000);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  EXPECT_EQ(contact.Query(I, {0, 0, 0.1}).points, 0);
  const bm::ContactResult c = contact.Query(I, {0, 0, -0.1});
  ASSERT_GT(c.points, 0);
  EXPECT_GT(c.force(2), 0.0);
  EXPECT_NEAR(c.force(0), 0.0, 1e-6 + 1e-3 * c.force(2));
  const bm::ContactResult c2 = contact.Query(I, {0, 0, -0.1 - 1e-4});
  const double slope = (c2.force(2) - c.force(2)) / -1e-4;
  EXPECT_NEAR(c.jacobian(2, 2), slope, 0.2 * std::abs(slope));
  EXPECT_LT(c.jacobian(2, 2), 0.0);
}

TEST(FeedBalance, TheAdvanceBalancesThrustAndCouplingForce) {
  const bm::TwistDrill drill;
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, drill);
  bm::FeedBalance fb(drill, model);
  const double full = bm::IntegrateEdges(drill, model, 0.02, 1000).thrustN;
  EXPECT_NEAR(fb.FullThrust(0.02, 1000), full, 0.01 * full);
  EXPECT_LT(fb.FullThrust(0.01, 1000), fb.FullThrust(0.02, 1000));
  // Full engagement, a spring of C = 0.8 N/mm pre-loaded with F0: thrust(f(u)) = F0 - C u.
  const double T = 0.001, n = 1000, C = 0.8, f0 = 5.0;
  const double u = fb.SolveAdvance(1.0, f0, C, n, T, 1.0);
  const double f = 60 * u / (n * T);
  EXPECT_NEAR(fb.FullThrust(f, n), f0 - C * u, 1e-6);
  EXPECT_GT(f, 0.005);
  EXPECT_LT(f, 0.02);
  EXPECT_EQ(fb.SolveAdvance(1.0, -1.0, C, n, T, 1.0), 0.0);        // pulled back: no cut
  EXPECT_EQ(fb.SolveAdvance(0.0, f0, C, n, T, 1.0), 0.0);          // not engaged: no cut
  EXPECT_DOUBLE_EQ(fb.SolveAdvance(1.0, f0, C, n, T, 1e-6), 1e-6); // the step limit holds
}

} // namespace
