// The CPU engine's incremental pass (bmIncrementalPass.h) against its full pass: the same frames
// through a one-thread engine with CullingOptions::incremental on and one with it off, each on its
// own copy of the voxmap, give the same FrameResult (every fixed-point sum and count) and the same
// fills, frame by frame: a reamer on the analytic glenoid fed along its axis with a lateral wobble
// of fractions of a voxel, a frame without motion, a jump across several voxels, cutting off (feed
// 0), a rotation change (the full pass, then the incremental pass again), a retraction that culls
// every block and a return; a drill on the bone block, also with materials varying per voxel;
// and the frames where the full pass runs instead.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "bmAnalyticGlenoid.h"
#include "bmBoneBlock.h"
#include "bmCpuEngine.h"
#include "bmEdgeQuadrature.h"
#include "bmPointShell.h"
#include "../Session/bmTestGlenoid.h"
#include "bmTestFeed.h"
#include "bmToolModel.h"

namespace {

struct Totals {
  int frames = 0, removingFrames = 0;
  int64_t removedVoxels = 0, engaged = 0, visited = 0;
  int64_t recomputed = 0; ///< elements the incremental pass's windows took
};

// Runs `inputs` through an incremental and a full-pass engine in lockstep, asserting identical
// results and fills after every frame; returns the incremental engine's frames run incrementally.
int64_t ExpectSameFrames(const bm::Voxmap& start, const bm::ToolModel& tool,
                         const bm::PointShell& shell, const std::vector<bm::FrameInput>& inputs,
                         const std::string& what, Totals& totals) {
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, tool);
  bm::Voxmap boneInc = start, boneFull = start;
  bm::CullingOptions on, off;
  off.incremental = false;
  bm::CpuEngine inc(boneInc, tool, shell, model, 1, on);
  bm::CpuEngine full(boneFull, tool, shell, model, 1, off);
  const size_t storage = size_t(start.StorageSize());
  for (size_t k = 0; k < inputs.size(); ++k) {
    const bm::FrameResult x = inc.Step(inputs[k]);
    const bm::FrameResult y = full.Step(inputs[k]);
    inc.SyncBone();
    full.SyncBone();
    SCOPED_TRACE(what + " frame " + std::to_string(k));
    EXPECT_EQ(x.thrustFixed, y.thrustFixed);
    EXPECT_EQ(x.torqueFixed, y.torqueFixed);
    EXPECT_EQ(x.forceTool, y.forceTool);
    EXPECT_EQ(x.visitedElements, y.visitedElements);
    EXPECT_EQ(x.engagedElements, y.engagedElements);
    EXPECT_EQ(x.engagedCutting, y.engagedCutting);
    EXPECT_EQ(x.removedFill, y.removedFill);
    EXPECT_EQ(x.removedVoxels, y.removedVoxels);
    EXPECT_EQ(x.sweptVolumeMm3, y.sweptVolumeMm3);
    if (!std::equal(boneInc.FillData(), boneInc.FillData() + storage, boneFull.FillData())) {
      ADD_FAILURE() << "fills differ";
      return -1;
    }
    ++totals.frames;
    totals.removingFrames += x.removedFill > 0;
    totals.removedVoxels += x.removedVoxels;
    totals.engaged += x.engagedCutting;
    totals.visited += x.visitedElements;
  }
  EXPECT_TRUE(boneInc == boneFull) << what << ": final voxmaps differ";
  EXPECT_EQ(full.IncrementalFrames(), 0);
  totals.recomputed = inc.IncrementalRecomputed();
  return inc.IncrementalFrames();
}

// A frame of tool pose (rot, pos), its motion since the previous frame, feed and speed.
bm::FrameInput Pose(const Eigen::Matrix3d& rot, const Eigen::Vector3d& pos,
                    const Eigen::Vector3d& prev, double feed, double rpm = 500) {
  bm::FrameInput in;
  in.rotation = rot;
  in.position = pos;
  in.motion = pos - prev;
  in.feedMmPerRev = feed;
  in.speedRpm = rpm;
  return in;
}

TEST(IncrementalPass, ReamerOnTheGlenoidGivesTheFullPassResults) {
  const auto reamer = bm::MakeTool(nlohmann::json{{"type", "reamer"}});
  const bm::PointShell shell = bm::PointShell::Build(*reamer, 128);
  const bm::Voxmap bone =
      bmtest::AnalyticGlenoidVoxmap(41.25 / 96); // the glenoid scene's voxmap 96
  const double zf = bm::ForemostCuttingZ(*reamer);
  // Along the glenoid's axis (world z out of the face): the lips' foremost point 0.1 mm above the
  // face centre, then down 0.004 mm a frame (0.01 voxel) with a lateral wobble of 0.02 mm.
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
  std::vector<bm::FrameInput> in;
  Eigen::Vector3d prev(0, 0, 0.1 - zf);
  double depth = 0.1;
  auto step = [&](double dz, double feed, double wobbleMm = 0.02) {
    depth -= dz;
    const double k = double(in.size());
    const Eigen::Vector3d pos =
        Eigen::Vector3d(wobbleMm * std::sin(0.7 * k), wobbleMm * std::cos(0.45 * k), depth) -
        rot * Eigen::Vector3d(0, 0, zf);
    in.push_back(Pose(rot, pos, prev, feed));
    prev = pos;
  };
  for (int k = 0; k < 120; ++k)
    step(0.004, 0.1);
  in.push_back(Pose(rot, prev, prev, 0.1)); // no motion: nothing removed, non-cutting blocks culled
  for (int k = 0; k < 20; ++k)
    step(0.004, 0.1);
  step(0.9, 0.1, 0.8); // across two voxels down and sideways in one frame
  for (int k = 0; k < 20; ++k)
    step(0.004, 0.0); // cutting off: feed 0 (removal only)
  // A tilt of 1 degree: A changes (the full pass), then stays (the incremental pass again).
  rot = Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (int k = 0; k < 40; ++k)
    step(0.004, 0.1);
  // Out of the bone (every block culled by rule 1), then back.
  const Eigen::Vector3d back = prev;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d out = back + Eigen::Vector3d(0, 0, 30.0 + k);
    in.push_back(Pose(rot, out, prev, 0.1));
    prev = out;
  }
  in.push_back(Pose(rot, back, prev, 0.1));
  prev = back;
  for (int k = 0; k < 20; ++k)
    step(0.004, 0.1);

  Totals t;
  const int64_t incremental = ExpectSameFrames(bone, *reamer, shell, in, "reamer", t);
  std::printf("reamer on the glenoid: %d frames identical, %lld incremental, %lld voxels removed, "
              "%lld engaged cutting element visits, %lld of %lld element visits recomputed in "
              "windows\n",
              t.frames, (long long)incremental, (long long)t.removedVoxels, (long long)t.engaged,
              (long long)t.recomputed, (long long)t.visited);
  // Every frame but the first and the tilt's ran incrementally (the three frames away from the
  // bone too: every block culled; the return visits its blocks in full).
  EXPECT_EQ(incremental, int64_t(in.size()) - 2);
  // The windows took a few elements (moves of 0.01-0.05 voxel), not every visited one.
  EXPECT_GT(t.recomputed, 0);
  EXPECT_LT(t.recomputed, t.visited / 10);
  EXPECT_GT(t.removedVoxels, 500); // the reamer cut: identical results prove something
  EXPECT_GT(t.engaged, 10000);
  EXPECT_GT(t.removingFrames, 150);
}

TEST(IncrementalPass, DrillOnTheBlockGivesTheFullPassResults) {
  const bm::TwistDrill drill;
  const bm::PointShell shell = bm::PointShell::Build(drill, 256);
  const bm::Voxmap bone = bm::MakeBoneBlock({5.0, 5.0, 1.5}, 64);
  bm::test::Feed axial;
  axial.frames = 150;
  bm::test::Feed oblique = axial; // sideways and down: rule 2 culls off the feed direction
  oblique.direction = Eigen::Vector3d(0.6, 0.2, -1.0).normalized();
  oblique.entry = Eigen::Vector3d(-0.6, -0.2, 0.0);
  bm::test::Feed coarse = axial; // 0.1 mm a frame: more than a voxel (0.078 mm) every frame
  coarse.stepMm = 0.1;
  coarse.frames = 20;
  for (const auto& [name, feed] :
       {std::pair{"axial", axial}, std::pair{"oblique", oblique}, std::pair{"coarse", coarse}}) {
    std::vector<bm::FrameInput> in;
    const Eigen::Matrix3d rot = bm::test::FeedRotation(feed);
    const Eigen::Vector3d dir = feed.direction.squaredNorm() > 0
                                    ? Eigen::Vector3d(feed.direction.normalized())
                                    : Eigen::Vector3d(-feed.axis.normalized());
    const double zf = bm::ForemostCuttingZ(drill);
    for (int k = 0; k < feed.frames; ++k) {
      const double depth = feed.startDepthMm + feed.stepMm * (k + 1);
      bm::FrameInput f;
      f.rotation = rot;
      f.position = feed.entry + dir * depth - rot * Eigen::Vector3d(0, 0, zf);
      f.motion = dir * feed.stepMm;
      f.feedMmPerRev = feed.feedMmPerRev;
      f.speedRpm = feed.speedRpm;
      in.push_back(f);
    }
    Totals t;
    const int64_t incremental = ExpectSameFrames(bone, drill, shell, in, name, t);
    std::printf("drill %s: %d frames identical, %lld incremental, %lld voxels removed\n", name,
                t.frames, (long long)incremental, (long long)t.removedVoxels);
    EXPECT_EQ(incremental, feed.frames - 1);
    EXPECT_GT(t.removedVoxels, 100);
  }
}

// Materials varying voxel by voxel (the weight an engaged element keeps in its list entry is
// delta x its voxel's material): the tilted entry of a drill into a block of three materials.
TEST(IncrementalPass, MaterialPerVoxelGivesTheFullPassResults) {
  const bm::TwistDrill drill;
  const bm::PointShell shell = bm::PointShell::Build(drill, 256);
  bm::Voxmap bone = bm::MakeBoneBlock({5.0, 5.0, 1.5}, 64);
  const auto dims = bone.Dims();
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        bone.SetMaterial(bone.Index(i, j, k), 0.5f + 0.25f * float((i + 2 * j + 3 * k) % 3));
  bm::test::Feed tilted;
  tilted.frames = 120;
  tilted.axis = Eigen::Vector3d(0.25, 0.1, 1.0).normalized();
  tilted.entry = Eigen::Vector3d(0.3, -0.2, 0.0);
  const Eigen::Matrix3d rot = bm::test::FeedRotation(tilted);
  const double zf = bm::ForemostCuttingZ(drill);
  std::vector<bm::FrameInput> in;
  for (int k = 0; k < tilted.frames; ++k) {
    const double depth = tilted.startDepthMm + tilted.stepMm * (k + 1);
    bm::FrameInput f;
    f.rotation = rot;
    f.position = tilted.entry - tilted.axis * depth - rot * Eigen::Vector3d(0, 0, zf);
    f.motion = -tilted.axis * tilted.stepMm;
    f.feedMmPerRev = tilted.feedMmPerRev;
    f.speedRpm = tilted.speedRpm;
    in.push_back(f);
  }
  Totals t;
  EXPECT_EQ(ExpectSameFrames(bone, drill, shell, in, "materials", t), tilted.frames - 1);
  EXPECT_GT(t.removedVoxels, 100);
  EXPECT_GT(t.engaged, 1000);
}

// An instantaneous shell turns with the spindle: A changes every frame, so every frame runs the
// full pass; and an engine on two threads never runs the incremental pass.
TEST(IncrementalPass, FallsBackWhereItDoesNotApply) {
  const bm::TwistDrill drill;
  const bm::PointShell inst = bm::PointShell::Build(drill, 128, bm::LipMode::Instantaneous);
  const bm::PointShell avg = bm::PointShell::Build(drill, 128);
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, drill);
  bm::test::Feed feed;
  feed.frames = 30;
  {
    bm::Voxmap bone = bm::MakeBoneBlock({5.0, 5.0, 1.5}, 64);
    bm::CpuEngine engine(bone, drill, inst, model, 1);
    bm::test::RunFeed(engine, drill, feed);
    EXPECT_EQ(engine.IncrementalFrames(), 0);
  }
  {
    bm::Voxmap bone = bm::MakeBoneBlock({5.0, 5.0, 1.5}, 64);
    bm::CpuEngine engine(bone, drill, avg, model, 2);
    bm::test::RunFeed(engine, drill, feed);
    EXPECT_EQ(engine.IncrementalFrames(), 0);
  }
  {
    bm::Voxmap bone = bm::MakeBoneBlock({5.0, 5.0, 1.5}, 64);
    bm::CpuEngine engine(bone, drill, avg, model, 1);
    bm::test::RunFeed(engine, drill, feed);
    EXPECT_EQ(engine.IncrementalFrames(), feed.frames - 1);
    engine.ForgetIncremental(); // the next frame runs the full pass
    feed.startDepthMm += feed.stepMm * feed.frames;
    bm::test::RunFeed(engine, drill, feed);
    EXPECT_EQ(engine.IncrementalFrames(), 2 * (feed.frames - 1));
    // Turned off (a benchmark's full pass): no more incremental frames; on again: a full pass
    // first, then incremental frames.
    engine.SetIncremental(false);
    feed.startDepthMm += feed.stepMm * feed.frames;
    bm::test::RunFeed(engine, drill, feed);
    EXPECT_EQ(engine.IncrementalFrames(), 0);
    engine.SetIncremental(true);
    feed.startDepthMm += feed.stepMm * feed.frames;
    bm::test::RunFeed(engine, drill, feed);
    EXPECT_EQ(engine.IncrementalFrames(), feed.frames - 1);
  }
}

} // namespace
