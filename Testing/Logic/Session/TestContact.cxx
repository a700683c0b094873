// Kim et al.'s pieces: the tool's signed distance field, the bone surface point shell and its
// flood-fill regeneration, the contact force; the feed balance of the cutting model; and the rigid
// contact of the tool's non-cutting parts along the axis (Docs/Interaction.md section 3).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "bmBoneSurfaceShell.h"
#include "bmFeedBalance.h"
#include "bmKimParkContact.h"
#include "bmProxy.h"
#include "bmSessionTestUtil.h"
#include "bmToolDistanceField.h"
#include "bmToolModel.h"

namespace {

TEST(ToolDistanceField, MatchesTheSphereOfABurr) {
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

TEST(ToolDistanceField, TheReamersFieldFollowsTheOutlineWithinItsLipschitzBound) {
  // The field is bilinear in (rho, z) on a table at half the box's spacing: within a quarter of
  // the spacing of the exact outline distance, its gradient the derivative of its value, and no
  // two points differ by more than the Lipschitz bound times their distance (the bound the
  // contact's candidate keys rely on).
  const auto reamer = bm::MakeTool({{"type", "reamer"}});
  const bm::ToolDistanceField sdf(*reamer, 256);
  const double h = sdf.Spacing();
  const Eigen::Vector3d lo = sdf.Lo(), span = sdf.Hi() - sdf.Lo();
  uint64_t state = 12345;
  auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / double(1ULL << 53);
  };
  int interior = 0;
  for (int n = 0; n < 4000; ++n) {
    const Eigen::Vector3d q =
        lo + Eigen::Vector3d(uniform() * span(0), uniform() * span(1), uniform() * span(2));
    ASSERT_TRUE(sdf.InGrid(q));
    Eigen::Vector3d g;
    const double d = sdf.Sample(q, g);
    EXPECT_EQ(d, sdf.Value(q));
    const double rho = std::hypot(q(0), q(1));
    EXPECT_NEAR(d, sdf.Exact(rho, q(2)), 0.25 * h) << q.transpose();
    // Inside one table cell (away from its edges) the value is smooth: central differences.
    const double e = 1e-6;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d dq = Eigen::Vector3d::Zero();
      dq(a) = e;
      if (sdf.InGrid(q + dq) && sdf.InGrid(q - dq) && rho > 1e-3) {
        const double fd = (sdf.Value(q + dq) - sdf.Value(q - dq)) / (2 * e);
        if (std::abs(fd - g(a)) < 1e-3)
          ++interior;
      }
    }
    const Eigen::Vector3d q2 =
        lo + Eigen::Vector3d(uniform() * span(0), uniform() * span(1), uniform() * span(2));
    EXPECT_LE(std::abs(sdf.Value(q2) - d), sdf.LipschitzBound() * (q2 - q).norm() + 1e-12);
    const Eigen::Vector3d q3 = q + 0.3 * h * (q2 - q).normalized();
    if (sdf.InGrid(q3)) {
      EXPECT_LE(std::abs(sdf.Value(q3) - d), sdf.LipschitzBound() * (q3 - q).norm() + 1e-12);
    }
  }
  EXPECT_GT(interior, 3 * 4000 * 95 / 100); // all but the few samples that straddle a cell edge
  EXPECT_LT(sdf.LipschitzBound(), 1.5);
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

// A small reamer (hemispherical head of radius 1 mm, 5 lips) whose non-cutting guide nipple
// (radius 0.25 mm, 0.3 mm ahead of the face) runs in a pilot hole (radius 0.35 mm, 0.6 mm deep) of
// a bone block. A robot-stiff device holds the tool 1 mm below the face, so the spindle-running
// proxy cuts the face's annulus at the balancing feed until the nipple meets the hole's bottom
// (tool origin at -0.3 mm). There the nipple is a rigid contact: the proxy stops, the bone under
// the nipple keeps its fill but for the last sub-step's graze, the cut stops, and the whole of the
// device's push is rendered through the coupling. The same reamer without a nipple (all lips) keeps
// cutting.
struct NippleRun {
  double finalZ = 0, minZ = 1e9; // proxy's tool origin, mm
  double lastFeed = 0, lastThrust = 0, lastForceZ = 0, pushN = 0;
  double removedMm3 = 0;                             // the whole run
  int64_t underNippleFill = 0, underNippleFill0 = 0; // fill below the hole's bottom, r < 0.25 mm
  double motionLast100 = 0; // |proxy z change| over the last 100 frames, mm
  double bottomCentreZ = 0; // centre of the highest bone voxel under the hole, mm
  double voxelMm = 0;
  int stopFrame = -1; // first frame of the rest at the end
};

/// holeR, holeDepth: the pilot hole, mm. partialWall: the wall voxels keep the fraction of their
/// width outside holeR (a partial-volume wall, as a CT import leaves it), so bone points of the
/// wall lie up to half a voxel inside holeR.
NippleRun RunNippleIntoPilotHole(double nippleRadiusMm, double holeR = 0.35, double holeDepth = 0.6,
                                 bool partialWall = false) {
  const bm::Scene scene = bm::test::GuidedReamerScene(nippleRadiusMm, 64);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  bm::Voxmap& bone = setup.Bone();
  const auto d = bone.Dims();
  const double h = bone.Spacing();
  NippleRun out;
  out.bottomCentreZ = -1e9;
  auto underNipple = [&](int64_t& sum) {
    sum = 0;
    for (int k = 0; k < d[2]; ++k)
      for (int jj = 0; jj < d[1]; ++jj)
        for (int i = 0; i < d[0]; ++i) {
          const auto w = bone.GridToWorld({double(i), double(jj), double(k)});
          if (std::hypot(w[0], w[1]) < 0.25 && w[2] < -holeDepth)
            sum += bone.GetFill(bone.Index(i, jj, k));
        }
  };
  for (int k = 0; k < d[2]; ++k)
    for (int jj = 0; jj < d[1]; ++jj)
      for (int i = 0; i < d[0]; ++i) {
        const auto w = bone.GridToWorld({double(i), double(jj), double(k)});
        const double r = std::hypot(w[0], w[1]);
        if (partialWall && w[2] >= -holeDepth && std::abs(r - holeR) < 0.5 * h) {
          const double outside = (r - holeR) / h + 0.5; // share of the voxel's width beyond holeR
          bone.SetFill(bone.Index(i, jj, k), bm::Voxmap::Fill(outside * bm::Voxmap::kFull));
        } else if (r <= holeR) {
          if (w[2] >= -holeDepth)
            bone.SetFill(bone.Index(i, jj, k), 0);
          else
            out.bottomCentreZ = std::max(out.bottomCentreZ, w[2]);
        }
      }
  bone.RebuildOccupancy();
  underNipple(out.underNippleFill0);

  bm::DeviceLimits robot;
  robot.maxForceN = 100;
  robot.maxStiffnessNPerMm = 20;
  robot.maxDampingNsPerMm = 0.1;
  bm::Proxy proxy(setup, robot, 0.001);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double speed = 1000, start = 0.1, hold = -1.0;
  proxy.Step({0, 0, start}, I, speed); // placed clear of the bone, the nipple in the hole
  std::vector<double> z;
  for (int k = 0; k < 250; ++k) {
    const bm::ProxyFrame f = proxy.Step({0, 0, hold}, I, speed);
    z.push_back(f.proxyPositionMm(2));
    out.minZ = std::min(out.minZ, f.proxyPositionMm(2));
    out.removedMm3 += f.removedVolumeMm3;
    out.lastFeed = f.feedMmPerRev;
    out.lastThrust = f.thrustN;
    out.lastForceZ = f.deviceForceN(2);
    out.pushN = proxy.Coupling().Stiffness() * (f.proxyPositionMm(2) - hold);
  }
  out.finalZ = z.back();
  out.voxelMm = bone.Spacing();
  for (size_t k = z.size() - 1; k > 0 && z[k - 1] == z.back(); --k)
    out.stopFrame = int(k - 1);
  out.motionLast100 = std::abs(z.back() - z[z.size() - 101]);
  underNipple(out.underNippleFill);
  return out;
}

TEST(Proxy, NonCuttingPartsAreARigidContactAlongTheAxisWhileCutting) {
  const NippleRun guided = RunNippleIntoPilotHole(0.25);
  const NippleRun plain = RunNippleIntoPilotHole(0.0);
  const double h = guided.voxelMm,
               stopZ = guided.bottomCentreZ + 0.3; // nipple tip on the bottom voxel
  std::cout << "[nipple] guided reamer: proxy stops at z " << guided.finalZ << " mm (contact at "
            << stopZ << ", lowest " << guided.minZ << ", at rest from frame " << guided.stopFrame
            << "), removed " << guided.removedMm3 << " mm^3, fill under the nipple "
            << guided.underNippleFill << " of " << guided.underNippleFill0 << ", last feed "
            << guided.lastFeed << " mm/rev, thrust " << guided.lastThrust << " N, device force "
            << guided.lastForceZ << " N (push " << guided.pushN
            << " N)\n[nipple] reamer without nipple: z " << plain.finalZ << " mm, removed "
            << plain.removedMm3 << " mm^3\n";
  // The lips cut the annulus before the nipple met the bottom.
  EXPECT_GT(guided.removedMm3, 0.05);
  // The nipple stopped at first contact (one half-voxel sub-step at most) and stays there.
  EXPECT_GT(guided.minZ, stopZ - 0.5 * h - 1e-3);
  EXPECT_LT(guided.finalZ, stopZ + h);
  EXPECT_LT(guided.motionLast100, 1e-9);
  // Under the non-cutting nipple the envelope removed no more than the graze of the last sub-step
  // into the first bone (under 10 % of one voxel layer below the nipple, about 140 voxels).
  const double layerFill = 3.14159265358979 * 0.25 * 0.25 / (h * h) * bm::Voxmap::kFull;
  EXPECT_LT(double(guided.underNippleFill0 - guided.underNippleFill), 0.1 * layerFill);
  // Rigid contact: no cut, and the device feels the whole push (K times the device's depth below
  // the proxy), sent back up.
  EXPECT_EQ(guided.lastFeed, 0.0);
  EXPECT_EQ(guided.lastThrust, 0.0);
  EXPECT_GT(guided.pushN, 10.0);
  EXPECT_NEAR(guided.lastForceZ, guided.pushN, 1e-6 * guided.pushN);
  // The same tool, all lips, in the same setup cuts on past the nipple's stop.
  EXPECT_LT(plain.finalZ, stopZ - 0.05);
  EXPECT_GT(plain.removedMm3, guided.removedMm3);
}

// The guided reamer in a snug through hole (radius = the nipple's) whose wall is partial volume,
// as a CT import leaves it: wall points lie up to half a voxel inside the nipple's radius, beside
// it rather than in front of it. The nipple must slide along that wall (the rim band) and the lips
// cut on like the nipple-less reamer's; counting those points as bone in front of the nipple
// stalled the glenoid session at its start.
TEST(Proxy, GuideNippleSlidesAlongAPartialVolumeHoleWall) {
  const NippleRun snug = RunNippleIntoPilotHole(0.25, 0.25, 2.0, true);
  const NippleRun plain = RunNippleIntoPilotHole(0.0, 0.25, 2.0, true);
  std::cout << "[nipple] snug partial-volume hole: proxy z " << snug.finalZ << " mm, removed "
            << snug.removedMm3 << " mm^3; without nipple: z " << plain.finalZ << " mm, removed "
            << plain.removedMm3 << " mm^3\n";
  EXPECT_LT(snug.finalZ, -0.3); // past the nipple-less reamer's 0.3 mm-deep guided stop above
  EXPECT_NEAR(snug.finalZ, plain.finalZ, 0.05);
  EXPECT_GT(snug.removedMm3, 0.8 * plain.removedMm3);
}

} // namespace
