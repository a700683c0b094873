// Determinism of the engines (bmEngine.h): the fixed-point totals and the removal do not depend on
// the thread count (CPU/Lazar and Zheng engines), and the culling rules of bmCpuEngine.h are exact
// (same totals and removal with and without them), frame by frame.
#include <gtest/gtest.h>

#include <cstdio>

#include "bmBoneBlock.h"
#include "bmCpuEngine.h"
#include "bmPointShell.h"
#include "bmTestFeed.h"
#include "bmZhengEngine.h"

namespace {

// Coarse grids (shell 39 um, voxels 78 um) and 5 um per frame keep these runs short; the drill goes
// ~1 mm deep, through entry and full engagement of its edges.
constexpr int kShellRes = 256;
constexpr int kVoxmapRes = 64;

struct Case {
  const char* name;
  bm::test::Feed feed;
  double blockDepthMm = 1.5;
};

std::vector<Case> Cases() {
  bm::test::Feed axial;
  axial.frames = 200;
  bm::test::Feed tilted = axial; // inclined entry off centre: partial engagement, lateral forces
  tilted.axis = Eigen::Vector3d(0.25, 0.1, 1.0).normalized();
  tilted.entry = Eigen::Vector3d(0.3, -0.2, 0.0);
  // Sideways and down at once (a burr-like cut): the motion is not along the axis, so rule 2 of
  // the culling (blocks whose normals cannot face the motion) is tested off the feed direction.
  bm::test::Feed oblique = axial;
  oblique.direction = Eigen::Vector3d(0.6, 0.2, -1.0).normalized();
  oblique.entry = Eigen::Vector3d(-0.6, -0.2, 0.0);
  // Through a 0.5 mm plate and out of its far side: elements stay engaged in voxels they emptied
  // (bmElementResidency.h) while whole bricks around them go void, which the block rule must not
  // cut short.
  bm::test::Feed through = axial;
  through.frames = 260;
  return {
      {"axial", axial}, {"tilted", tilted}, {"oblique", oblique}, {"breakthrough", through, 0.5}};
}

class EngineDeterminism : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    Drill = new bm::TwistDrill();
    Shell = new bm::PointShell(bm::PointShell::Build(*Drill, kShellRes));
    InstShell =
        new bm::PointShell(bm::PointShell::Build(*Drill, kShellRes, bm::LipMode::Instantaneous));
  }
  static void TearDownTestSuite() {
    delete Drill;
    delete Shell;
    delete InstShell;
  }
  static bm::Voxmap Block(double depthMm = 1.5) {
    return bm::MakeBoneBlock({5.0, 5.0, depthMm}, kVoxmapRes);
  }

  static inline bm::TwistDrill* Drill = nullptr;
  static inline bm::PointShell* Shell = nullptr;
  static inline bm::PointShell* InstShell = nullptr;
};

struct Outcome {
  std::vector<bm::FrameResult> frames;
  bm::Voxmap bone;
};

// Same totals and removal, frame by frame, and the same final voxmap.
void ExpectSame(const Outcome& a, const Outcome& b, const std::string& what) {
  ASSERT_EQ(a.frames.size(), b.frames.size());
  int64_t removedVoxels = 0, engaged = 0;
  double maxThrust = 0;
  for (size_t k = 0; k < a.frames.size(); ++k) {
    const auto &x = a.frames[k], &y = b.frames[k];
    ASSERT_EQ(x.thrustFixed, y.thrustFixed) << what << " frame " << k;
    ASSERT_EQ(x.torqueFixed, y.torqueFixed) << what << " frame " << k;
    ASSERT_EQ(x.forceTool, y.forceTool) << what << " frame " << k;
    ASSERT_EQ(x.removedVoxels, y.removedVoxels) << what << " frame " << k;
    ASSERT_EQ(x.removedFill, y.removedFill) << what << " frame " << k;
    ASSERT_EQ(x.sweptVolumeMm3, y.sweptVolumeMm3) << what << " frame " << k;
    removedVoxels += x.removedVoxels;
    engaged += x.engagedCutting;
    maxThrust = std::max(maxThrust, x.thrustN);
  }
  EXPECT_TRUE(a.bone == b.bone) << what << ": final voxmaps differ";
  // The occupancy the removal kept current is the occupancy of the fills (the engines pass each
  // removal's brick along rather than working it out again).
  for (const bm::Voxmap* v : {&a.bone, &b.bone}) {
    bm::Voxmap recount = *v;
    recount.RebuildOccupancy();
    const int64_t bricks = int64_t(v->BrickDims()[0]) * v->BrickDims()[1] * v->BrickDims()[2];
    for (int64_t k = 0; k < bricks; ++k)
      ASSERT_EQ(v->BrickCount(k), recount.BrickCount(k)) << what << ": brick " << k;
  }
  std::printf("%-28s %zu frames identical: %lld voxels removed, max thrust %.3f N, last %.3f N / "
              "%.3f N mm\n",
              what.c_str(), a.frames.size(), (long long)removedVoxels, maxThrust,
              a.frames.back().thrustN, a.frames.back().torqueNmm);
  // The run did cut: otherwise identical results would prove nothing.
  EXPECT_GT(removedVoxels, 1000);
  EXPECT_GT(engaged, 0);
  EXPECT_GT(maxThrust, 1.0);
}

TEST_F(EngineDeterminism, CpuEngineSameResultsOnOneAndTwoThreads) {
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, *Drill);
  for (const auto& c : Cases())
    for (const bm::PointShell* shell : {Shell, InstShell}) {
      Outcome runs[2];
      for (int t = 0; t < 2; ++t) {
        runs[t].bone = Block(c.blockDepthMm);
        bm::CpuEngine engine(runs[t].bone, *Drill, *shell, model, t + 1);
        ASSERT_EQ(engine.Threads(), t + 1);
        runs[t].frames = bm::test::RunFeed(engine, *Drill, c.feed);
      }
      ExpectSame(runs[0], runs[1],
                 std::string("cpu 1 vs 2 threads ") + c.name + (shell == InstShell ? " inst" : ""));
    }
}

TEST_F(EngineDeterminism, ZhengEngineSameResultsOnOneAndTwoThreads) {
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Zheng, *Drill);
  // Zheng's pass visits every element each frame (no culling): two cases keep it short.
  for (const auto& c : Cases()) {
    if (std::string(c.name) != "axial" && std::string(c.name) != "tilted")
      continue;
    Outcome runs[2];
    for (int t = 0; t < 2; ++t) {
      runs[t].bone = Block(c.blockDepthMm);
      bm::ZhengEngine engine(runs[t].bone, *Drill, *Shell, model, t + 1);
      runs[t].frames = bm::test::RunFeed(engine, *Drill, c.feed);
    }
    ExpectSame(runs[0], runs[1], std::string("zheng 1 vs 2 threads ") + c.name);
  }
}

TEST_F(EngineDeterminism, CullingRulesAreExact) {
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, *Drill);
  for (const auto& c : Cases()) {
    Outcome on, off;
    int64_t visitedOn = 0, visitedOff = 0;
    on.bone = Block(c.blockDepthMm);
    off.bone = Block(c.blockDepthMm);
    {
      bm::CpuEngine engine(on.bone, *Drill, *Shell, model, 2, bm::CullingOptions{true, true});
      on.frames = bm::test::RunFeed(engine, *Drill, c.feed);
    }
    {
      bm::CpuEngine engine(off.bone, *Drill, *Shell, model, 2, bm::CullingOptions{false, false});
      off.frames = bm::test::RunFeed(engine, *Drill, c.feed);
    }
    for (size_t k = 0; k < on.frames.size(); ++k) {
      visitedOn += on.frames[k].visitedElements;
      visitedOff += off.frames[k].visitedElements;
    }
    std::printf("culling %s: %lld element visits with culling, %lld without (%.1f %%)\n", c.name,
                (long long)visitedOn, (long long)visitedOff, 100.0 * visitedOn / visitedOff);
    EXPECT_LT(visitedOn, visitedOff / 2); // the rules do cull
    ExpectSame(on, off, std::string("culling on vs off ") + c.name);
    // Each rule alone is exact too.
    for (bm::CullingOptions opt :
         {bm::CullingOptions{true, false}, bm::CullingOptions{false, true}}) {
      Outcome one;
      one.bone = Block(c.blockDepthMm);
      bm::CpuEngine engine(one.bone, *Drill, *Shell, model, 1, opt);
      one.frames = bm::test::RunFeed(engine, *Drill, c.feed);
      ExpectSame(on, one,
                 std::string(opt.blocks ? "block rule only " : "motion rule only ") + c.name);
    }
  }
}

} // namespace
