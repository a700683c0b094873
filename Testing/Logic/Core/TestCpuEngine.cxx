// The CPU engine's own bookkeeping (bmCpuEngine.h): its packed residency words follow
// ElementResidency's rule, a block that was not visited in the previous frame forgets its
// elements' residency, its removal-request lists keep their requests and sentinel as they grow,
// and it refuses more threads than it has removal parts for. (Its results against the other
// engines: TestEngineDeterminism, TestOpenCLIdentity.)
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "bmBoneBlock.h"
#include "bmCpuEngine.h"
#include "bmElementResidency.h"
#include "bmFrameGeometry.h"
#include "bmMorton.h"
#include "bmPointShell.h"
#include "bmTestFeed.h"

namespace {

TEST(PackedResidency, FollowsElementResidencysRule) {
  // One element's visits: voxels from a small set (-1 = outside), frames with gaps, fills bone
  // or void; the word and the block's last frame against the 16-byte struct, visit by visit.
  std::mt19937 rng(7);
  bm::ElementResidency reference;
  uint64_t word = 0;
  uint32_t lastFrame = 0, frame = 0;
  int staysSeen = 0, gapsSeen = 0;
  for (int k = 0; k < 20000; ++k) {
    const bool gap = rng() % 5 == 0;
    frame += gap ? 2 + rng() % 3 : 1;
    const int64_t idx = int64_t(rng() % 4) - 1;
    const bm::Voxmap::Fill fill = rng() % 3 == 0 ? 0 : bm::Voxmap::kFull / 2;
    const bool stays = bm::PackedResidency::Stays(word, lastFrame + 1 == frame, idx);
    ASSERT_EQ(stays, reference.Stays(frame, idx)) << "visit " << k;
    const bool engaged = idx >= 0 && (stays || fill > 0);
    ASSERT_EQ(engaged, reference.Visit(frame, idx, fill)) << "visit " << k;
    word = bm::PackedResidency::Word(idx, engaged);
    lastFrame = frame;
    staysSeen += stays;
    gapsSeen += gap;
  }
  EXPECT_GT(staysSeen, 1000); // the rule's both branches were exercised
  EXPECT_GT(gapsSeen, 1000);
}

// Engaged elements, then a frame in which every block is culled (the tool away from the bone),
// then the voxels the elements were in are emptied and the tool comes back to the same pose: its
// elements did not stay in their voxels in consecutive frames, so none may count as still
// engaged; the engine must give what an engine without history gives.
TEST(CpuEngine, ABlockNotVisitedInTheLastFrameForgetsItsResidency) {
  const bm::TwistDrill drill;
  const bm::PointShell shell = bm::PointShell::Build(drill, 256);
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, drill);
  for (int threads : {1, 2}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    bm::Voxmap bone = bm::MakeBoneBlock({5.0, 5.0, 1.5}, 64);
    bm::CpuEngine engine(bone, drill, shell, model, threads);
    bm::test::Feed feed;
    feed.frames = 120;
    const auto fed = bm::test::RunFeed(engine, drill, feed);
    ASSERT_GT(fed.back().engagedCutting, 0);

    // The last pose of the feed, still and querying only.
    bm::FrameInput at;
    at.rotation = bm::test::FeedRotation(feed);
    at.position = Eigen::Vector3d(0, 0, -(feed.startDepthMm + feed.stepMm * feed.frames)) -
                  at.rotation * Eigen::Vector3d(0, 0, bm::ForemostCuttingZ(drill));
    at.removeMaterial = false;
    ASSERT_GT(engine.Step(at).engagedCutting, 0); // the same voxels, consecutive: still engaged

    bm::FrameInput away = at;
    away.position += Eigen::Vector3d(0, 0, 50);
    EXPECT_EQ(engine.Step(away).visitedElements, 0); // every block culled

    const bm::FrameGeometry G(at, shell, bone);
    for (uint64_t code : shell.Codes())
      if (const int64_t idx = G.VoxelOf(bm::ElementCoords(code)); idx >= 0)
        bone.SetFill(idx, 0);
    bm::Voxmap copy = bone;
    bm::CpuEngine fresh(copy, drill, shell, model, threads);
    const bm::FrameResult expected = fresh.Step(at), got = engine.Step(at);
    EXPECT_GT(expected.visitedElements, 0); // the blocks hold bone around the emptied voxels
    EXPECT_EQ(expected.engagedElements, 0);
    EXPECT_EQ(got.visitedElements, expected.visitedElements);
    EXPECT_EQ(got.engagedElements, expected.engagedElements);
    EXPECT_EQ(got.thrustFixed, expected.thrustFixed);
    EXPECT_EQ(got.torqueFixed, expected.torqueFixed);
  }
}

TEST(RequestList, GrowsKeepingItsRequestsAndSentinel) {
  bm::RequestList list;
  EXPECT_EQ(list.Size(), 0u);
  EXPECT_EQ(list.End()[-1].voxel, bm::RequestList::kNoVoxel);
  for (int round = 0; round < 6; ++round) {
    list.Reserve(100);
    bm::Voxmap::RemovalRequest* w = list.End();
    for (int i = 0; i < 100; ++i)
      *w++ = {int64_t(100 * round + i), i + 1, round};
    list.SetEnd(w);
  }
  ASSERT_EQ(list.Size(), 600u);
  for (size_t i = 0; i < list.Size(); ++i) {
    EXPECT_EQ(list.Data()[i].voxel, int64_t(i));
    EXPECT_EQ(list.Data()[i].units, int32_t(i % 100 + 1));
  }
  EXPECT_EQ(list.Data()[-1].voxel, bm::RequestList::kNoVoxel);
  list.Clear();
  EXPECT_EQ(list.Size(), 0u);
  EXPECT_EQ(list.End()[-1].voxel, bm::RequestList::kNoVoxel);
}

TEST(CpuEngine, RefusesMoreThreadsThanItHasRemovalPartsFor) {
  const bm::TwistDrill drill;
  const bm::PointShell shell = bm::PointShell::Build(drill, 64);
  const bm::ForceModel model = bm::ForceModel::Default(bm::Method::Lazar, drill);
  bm::Voxmap bone = bm::MakeBoneBlock({5.0, 5.0, 1.5}, 32);
  EXPECT_THROW(bm::CpuEngine(bone, drill, shell, model, bm::CpuEngine::kMaxThreads + 1),
               std::invalid_argument);
  EXPECT_NO_THROW(bm::CpuEngine(bone, drill, shell, model, 2));
}

} // namespace
