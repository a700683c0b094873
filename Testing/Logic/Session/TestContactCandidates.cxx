// KimParkContact's candidate points (SetCandidateRadius) are exact: along a wandering path of
// tool poses, with and without dead band, with and without a depth cap (SetDepthCap), for the
// whole tool and for the reamer's leading part,
// across changes of orientation and of the shell (Boolean cuts), every query equals, bit for bit,
// the full scan of a contact without candidates on the same shell and field, also when the engine's
// removal changes the shell under them and when the tool jumps between places across the axis.
// KimParkContact::Touches, the sweep's first-contact test, answers as the full query's count.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "bmKimParkContact.h"
#include "bmMachiningSetup.h"
#include "bmSessionTestUtil.h"

namespace {

void ExpectSame(const bm::ContactResult& a, const bm::ContactResult& b) {
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.jacobian, b.jacobian);
  EXPECT_EQ(a.maxDepthMm, b.maxDepthMm);
  EXPECT_EQ(a.normal, b.normal);
}

TEST(ContactCandidates, QueriesEqualTheFullScan) {
  const bm::Scene scene = bm::test::GuidedReamerScene(0.25, 48);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  const double h = setup.Bone().Spacing();
  const bm::ToolDistanceField sdf(setup.Tool(), 64);
  bm::BoneSurfaceShell shell(setup.Bone());
  bm::KimParkContact full(sdf, shell), cached(sdf, shell);
  cached.SetCandidateRadius(2 * h);
  EXPECT_GE(sdf.LipschitzBound(), 1.0 - 1e-6); // a distance field has slope 1 somewhere
  // The cutting method's depth cap (on this Boolean-cut block every voxel is full or void: no
  // slivers, so the cap changes nothing here, and the cached path must agree).
  bm::KimParkContact fullCap(sdf, shell), cachedCap(sdf, shell);
  fullCap.SetDepthCap(1.5 * h);
  cachedCap.SetDepthCap(1.5 * h);
  cachedCap.SetCandidateRadius(2 * h);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(-0.5 * h, 0.5 * h);
  Eigen::Vector3d p(0, 0, 0.05);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  int touching = 0, partTouching = 0, leadingTouching = 0;
  for (int it = 0; it < 600; ++it) {
    p += Eigen::Vector3d(step(rng), step(rng), step(rng) - 0.05 * h); // sinking slowly
    p(2) = std::max(p(2), -0.6);
    if (it % 150 == 75) // a new orientation: the candidates are gathered again
      R = Eigen::AngleAxisd(0.05 * (it / 150 + 1), Eigen::Vector3d(1, 1, 0).normalized())
              .toRotationMatrix();
    if (it % 100 == 50) { // the shell changes under the candidates
      int64_t fill = 0;
      cached.Cut(R, p, 0.5 * h, fill);
    }
    for (double band : {0.0, h}) {
      const bm::ContactResult a = full.Query(R, p, band), b = cached.Query(R, p, band);
      ExpectSame(a, b);
      // A sweep's question, whether any point touches (stopping at the first), answers as the
      // full query's count does, for the whole tool and each part, with and without the cap.
      for (bm::ToolPart part :
           {bm::ToolPart::Whole, bm::ToolPart::Leading, bm::ToolPart::NonCuttingLeading}) {
        const double rim = part == bm::ToolPart::Whole ? 0.0 : h;
        EXPECT_EQ(cached.Touches(R, p, band, part, rim),
                  full.Query(R, p, band, part, rim).points > 0);
        EXPECT_EQ(cachedCap.Touches(R, p, band, part, rim),
                  fullCap.Query(R, p, band, part, rim).points > 0);
        leadingTouching += part == bm::ToolPart::Leading && cached.Touches(R, p, band, part, rim);
      }
      touching += a.points > 0;
      const bm::ContactResult c = full.Query(R, p, band, bm::ToolPart::NonCuttingLeading, h),
                              d = cached.Query(R, p, band, bm::ToolPart::NonCuttingLeading, h);
      ExpectSame(c, d);
      partTouching += c.points > 0;
      const bm::ContactResult e = fullCap.Query(R, p, band);
      ExpectSame(e, cachedCap.Query(R, p, band));
      ExpectSame(fullCap.Query(R, p, band, bm::ToolPart::NonCuttingLeading, h),
                 cachedCap.Query(R, p, band, bm::ToolPart::NonCuttingLeading, h));
      ExpectSame(e, a);
    }
    if (HasFailure())
      break;
  }
  std::cout << "[candidates] " << touching << " whole-tool, " << partTouching
            << " non-cutting leading and " << leadingTouching
            << " leading-part queries in contact; " << full.Scans() << " full scans, "
            << cached.Scans() << " gathers (" << cachedCap.Scans() << " with the cap)\n";
  EXPECT_GT(touching, 100); // the path does press into the bone
  EXPECT_GT(leadingTouching, 50);
  EXPECT_GT(partTouching, 10);
  EXPECT_LT(cached.Scans(), full.Scans() / 4);
  EXPECT_LT(cachedCap.Scans(), fullCap.Scans() / 4);
}

// The engine cuts under the candidates every step (BoneSurfaceShell::Sync regenerates the
// shell, the candidates gather again only the bricks that changed), while the tool sinks and
// jumps across the axis between three places farther apart than the candidate radius (a lateral
// limit cycle): every query still equals the full scan, bit for bit, the candidates are gathered
// about once per place, not once per step, and the shell holds the points a new shell of the cut
// bone holds.
TEST(ContactCandidates, FollowTheEnginesRemovalAndALateralCycleExactly) {
  const bm::Scene scene = bm::test::GuidedReamerScene(0.25, 48);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  const double h = setup.Bone().Spacing();
  const bm::ToolDistanceField sdf(setup.Tool(), 64);
  bm::BoneSurfaceShell shell(setup.Bone());
  bm::KimParkContact full(sdf, shell), cached(sdf, shell);
  cached.SetCandidateRadius(2 * h);
  bm::KimParkContact fullCap(sdf, shell), cachedCap(sdf, shell);
  fullCap.SetDepthCap(h);
  cachedCap.SetDepthCap(h);
  cachedCap.SetCandidateRadius(2 * h);
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const std::array<Eigen::Vector3d, 3> places{Eigen::Vector3d(2.5 * h, 0, 0),
                                              Eigen::Vector3d(-1.5 * h, 2.2 * h, 0),
                                              Eigen::Vector3d(-1.5 * h, -2.2 * h, 0)};
  Eigen::Vector3d prev(places[0](0), places[0](1), 0.1);
  int64_t removed = 0;
  int touching = 0, capped = 0; // queries where slivers deeper than the cap did not push
  int leadingTouching = 0;
  const int steps = 240;
  const double kSink = 0.0015; // mm a step
  for (int it = 0; it < steps; ++it) {
    const double z = 0.02 - kSink * it; // sinking into the bone's top face (z = 0)
    const Eigen::Vector3d p = places[size_t(it % 3)] + Eigen::Vector3d(0, 0, z);
    bm::FrameInput in;
    in.position = p;
    in.motion = Eigen::Vector3d(0, 0, -kSink);
    in.feedMmPerRev = 0.01;
    in.speedRpm = 1000;
    const bm::FrameResult r = setup.GetEngine().Step(in);
    removed += r.removedVoxels;
    if (r.removedVoxels > 0) {
      Eigen::Vector3d lo0, hi0, lo1, hi1;
      cached.ToolBox(R, prev, lo0, hi0);
      cached.ToolBox(R, p, lo1, hi1);
      shell.Sync(lo0.cwiseMin(lo1), hi0.cwiseMax(hi1));
    }
    prev = p;
    for (double band : {0.0, h}) {
      const bm::ContactResult a = full.Query(R, p, band), b = cached.Query(R, p, band);
      ExpectSame(a, b);
      // A sweep's question, whether any point touches (stopping at the first), answers as the
      // full query's count does, for the whole tool and each part, with and without the cap.
      for (bm::ToolPart part :
           {bm::ToolPart::Whole, bm::ToolPart::Leading, bm::ToolPart::NonCuttingLeading}) {
        const double rim = part == bm::ToolPart::Whole ? 0.0 : h;
        EXPECT_EQ(cached.Touches(R, p, band, part, rim),
                  full.Query(R, p, band, part, rim).points > 0);
        EXPECT_EQ(cachedCap.Touches(R, p, band, part, rim),
                  fullCap.Query(R, p, band, part, rim).points > 0);
        leadingTouching += part == bm::ToolPart::Leading && cached.Touches(R, p, band, part, rim);
      }
      touching += a.points > 0;
      ExpectSame(full.Query(R, p, band, bm::ToolPart::NonCuttingLeading, h),
                 cached.Query(R, p, band, bm::ToolPart::NonCuttingLeading, h));
      const bm::ContactResult e = fullCap.Query(R, p, band);
      ExpectSame(e, cachedCap.Query(R, p, band));
      EXPECT_LE(e.points, a.points);
      capped += e.points < a.points;
    }
    if (it % 60 == 59) { // Sync, reading only the bricks that lost a voxel, keeps the surface
      // (each point's normal, refreshed once per flood, bit for bit a new shell's)
      auto points = [](const bm::BoneSurfaceShell& sh) {
        std::vector<std::array<double, 4>> v;
        const Eigen::Vector3d big = Eigen::Vector3d::Constant(1e9);
        sh.ForEachIn(-big, big, [&](const bm::SurfacePoint& sp) {
          v.push_back({double(sp.voxel), sp.normal(0), sp.normal(1), sp.normal(2)});
        });
        std::sort(v.begin(), v.end());
        return v;
      };
      EXPECT_EQ(points(shell), points(bm::BoneSurfaceShell(setup.Bone())));
    }
    if (HasFailure())
      break;
  }
  std::cout << "[candidates] " << removed << " voxels removed, " << touching
            << " queries in contact (" << capped << " with slivers beyond the cap); "
            << cached.Scans() << " gathers, " << cached.RefreshedBricks()
            << " bricks gathered again; the leading part touched in " << leadingTouching << "\n";
  EXPECT_GT(removed, 0);
  EXPECT_GT(leadingTouching, 10);
  EXPECT_GT(touching, 100);
  EXPECT_GT(cached.RefreshedBricks(), 0);
  // Each place's set holds while the sinking stays within the radius: 3 x (0.36 mm / 0.1 mm + 1)
  // gathers at most (one per step, 240, with a single set).
  EXPECT_LE(cached.Scans(), 3 * (int(std::ceil(kSink * steps / (2 * h))) + 1));
}

} // namespace

// The sliver rule itself: a voxel deeper than the cap inside the tool pushes when it holds bone,
// not when it holds a sliver of it (under the sliver fraction), cached or not; within the cap
// every point pushes.
TEST(ContactCandidates, OnlySliversDeeperThanTheCapStopPushing) {
  const bm::Scene scene = bm::test::GuidedReamerScene(0.25, 48);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  bm::Voxmap& bone = setup.Bone();
  const double h = bone.Spacing();
  const bm::ToolDistanceField sdf(setup.Tool(), 64);
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d p(0, 0, -0.3); // the tool pressed 0.3 mm into the block's top face
  auto query = [&](double cap, bool cached) {
    bm::BoneSurfaceShell shell(bone);
    bm::KimParkContact c(sdf, shell);
    if (cap > 0)
      c.SetDepthCap(cap);
    if (cached)
      c.SetCandidateRadius(2 * h);
    return c.Query(R, p, 0.0);
  };
  const bm::ContactResult all = query(0, false);
  ASSERT_GT(all.maxDepthMm, 2 * h); // points deeper than a cap of two voxels
  // Full bone deeper than the cap still pushes: the same contact.
  ExpectSame(query(2 * h, false), all);
  ExpectSame(query(2 * h, true), all);
  // Every voxel made a sliver (4 % full, under the default 5 %): those deeper than the cap stop
  // pushing.
  const auto d = bone.Dims();
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        if (const int64_t v = bone.Index(i, j, k); bone.GetFill(v) > 0)
          bone.SetFill(v, bm::Voxmap::kFull / 25);
  const bm::ContactResult slivers = query(2 * h, false);
  ExpectSame(query(2 * h, true), slivers);
  EXPECT_GT(slivers.points, 0);
  EXPECT_LT(slivers.points, all.points);
  EXPECT_LE(slivers.maxDepthMm, 2 * h + 1e-12);
}
