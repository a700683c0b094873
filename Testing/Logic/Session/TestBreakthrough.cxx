// The breakthrough plunge (bmBreakthrough.h) and the scripted trained hand that stops at it
// (ScriptedDeviceOptions::stopAtBreakthrough): the measurement on records made up to show each
// case, the hand's reaction to the rendered force giving way, and the drilling scene's force-mode
// session, through the 1.5 mm plate with a hand that pushes on and with a trained one, and the
// same session with the proxy's fast paths against its reference path, frame for frame.
#include <gtest/gtest.h>

#include <cstring>
#include <iostream>
#include <vector>

#include "bmBreakthrough.h"
#include "bmHapticSession.h"
#include "bmSceneOverrides.h"
#include "bmScriptedDevice.h"
#include "bmSessionBuilder.h"

namespace {

/// A record: `cut` frames advancing 0.01 mm each with thrust, then `through` frames advancing
/// `speed` mm each without, then `rest` frames at rest (depth in proxyPos[2], mm).
std::vector<bm::FrameRecord> Made(int cut, int through, double speed, int rest) {
  std::vector<bm::FrameRecord> v;
  double depth = 0;
  auto add = [&](double thrust) {
    bm::FrameRecord f;
    f.frame = int64_t(v.size());
    f.timeS = 0.001 * double(v.size());
    f.thrustN = thrust;
    f.proxyPos = {0, 0, depth};
    v.push_back(f);
  };
  for (int i = 0; i < cut; ++i, depth += 0.01)
    add(20);
  for (int i = 0; i < through; ++i, depth += speed)
    add(0);
  for (int i = 0; i < rest; ++i)
    add(0);
  return v;
}

double Depth(const bm::FrameRecord& f) {
  return f.proxyPos[2];
}

TEST(Breakthrough, PlungeIsTheTravelPastTheLastCutUntilTheToolRests) {
  // 100 cutting frames (0.99 mm deep at the last), 30 frames at 0.1 mm a frame, then at rest.
  const bm::Breakthrough b = bm::MeasureBreakthrough(Made(100, 30, 0.1, 80), Depth);
  ASSERT_TRUE(b.found);
  EXPECT_NEAR(b.depthMm, 0.99, 1e-12);
  EXPECT_NEAR(b.timeS, 0.099, 1e-12);
  EXPECT_NEAR(b.plungeMm, 0.01 + 30 * 0.1, 1e-9); // the last cutting frame's own step, then 30
  EXPECT_TRUE(b.stopped);
  EXPECT_NEAR(b.stopS, 0.031, 1e-9);
  // Still moving when the record ends (the runaway rule paused it): a lower bound.
  const bm::Breakthrough m = bm::MeasureBreakthrough(Made(100, 60, 0.1, 0), Depth);
  ASSERT_TRUE(m.found);
  EXPECT_FALSE(m.stopped);
  EXPECT_NEAR(m.plungeMm, 0.01 + 59 * 0.1, 1e-9);
  // No breakthrough: still cutting; too little cutting before; an advance under 0.5 mm.
  EXPECT_FALSE(bm::MeasureBreakthrough(Made(300, 0, 0, 0), Depth).found);
  EXPECT_FALSE(bm::MeasureBreakthrough(Made(5, 30, 0.1, 10), Depth).found);
  EXPECT_FALSE(bm::MeasureBreakthrough(Made(100, 4, 0.1, 100), Depth).found);
  EXPECT_FALSE(bm::MeasureBreakthrough({}, Depth).found);
}

TEST(Breakthrough, ATrainedHandLetsGoAfterItsReactionWhenTheResistanceGivesWay) {
  bm::ScriptedDeviceOptions o;
  o.mode = bm::ScriptMode::Force;
  o.appliedForceN = 2.0;
  o.stopAtBreakthrough = true;
  bm::ScriptedDevice hand(o);
  const double dt = 0.001;
  int k = 0;
  auto frame = [&](double resistN) {
    hand.Write(o.axis * resistN); // what the session renders back, out of the bone
    hand.Advance(++k * dt, dt);
  };
  for (int i = 0; i < 100; ++i)
    frame(2.0); // the bone holds the push
  EXPECT_LT(hand.BreakthroughFeltAtS(), 0);
  EXPECT_NEAR(hand.HandForce(k * dt).norm(), 2.0, 1e-12);
  frame(1.2); // 60 % of the peak: still held
  EXPECT_LT(hand.BreakthroughFeltAtS(), 0);
  frame(0.5); // gave way
  const double felt = hand.BreakthroughFeltAtS();
  EXPECT_NEAR(felt, k * dt, 1e-12);
  EXPECT_NEAR(hand.HandForce(felt + 0.099).norm(), 2.0, 1e-12); // the reaction time
  EXPECT_NEAR(hand.HandForce(felt + 0.125).norm(), 1.0, 1e-9);  // halfway through letting go
  EXPECT_EQ(hand.HandForce(felt + 0.2).norm(), 0.0);
  // A hand that was never held by bone (a push into air) does not take a fall for breakthrough.
  bm::ScriptedDevice air(o);
  air.Write(Eigen::Vector3d::Zero());
  for (int i = 1; i <= 100; ++i)
    air.Advance(i * dt, dt);
  EXPECT_LT(air.BreakthroughFeltAtS(), 0);
  // Out of range: refused by name.
  o.reactionS = 3;
  EXPECT_THROW(bm::ScriptedDevice{o}, std::invalid_argument);
}

// The drilling scene at voxmap 64 in force mode, frames back to back: a hand that pushes on
// plunges until the runaway rule stops it; a trained hand stops within a few mm.
TEST(Breakthrough, TheDrillingSessionReportsThePlungeAndATrainedHandStopsIt) {
  bm::SceneOverrides ov;
  ov.voxmapResolution = 64;
  const bm::Scene scene = bm::ApplyOverrides(bm::ResolveScene("drilling"), ov);
  auto run = [&](bool trained) {
    bm::SessionRequest r;
    r.mode = bm::ScriptMode::Force;
    r.realTime = false;
    r.durationS = 2.5;
    r.stopAtBreakthrough = trained;
    bm::BuiltSession b = bm::BuildSession(scene, r);
    b.options.recordCapacity = 4000;
    bm::HapticSession session(*b.setup, b.device, b.options);
    session.Start();
    EXPECT_TRUE(session.WaitUntilPaused(600));
    session.Stop();
    std::vector<bm::FrameRecord> rec;
    session.DrainRecords(rec);
    return bm::MeasureBreakthrough(rec, [&](const bm::FrameRecord& f) {
      return bm::ToolDepthMm(*b.setup, Eigen::Vector3d(f.proxyPos[0], f.proxyPos[1], f.proxyPos[2]),
                             bm::ToolRotationFromQuaternion(f.deviceQuat));
    });
  };
  const bm::Breakthrough pushOn = run(false), trained = run(true);
  std::cout << "[breakthrough] pushing on: through at " << pushOn.depthMm << " mm, plunge "
            << pushOn.plungeMm << " mm (stopped " << pushOn.stopped << "); trained hand: plunge "
            << trained.plungeMm << " mm, stopped after " << trained.stopS << " s\n";
  ASSERT_TRUE(pushOn.found);
  ASSERT_TRUE(trained.found);
  // Through the 1.5 mm plate: the drill's point (0.75 mm tall) has left it.
  EXPECT_GT(pushOn.depthMm, 1.5);
  EXPECT_LT(pushOn.depthMm, 1.5 + 1.0);
  EXPECT_FALSE(pushOn.stopped);
  EXPECT_GT(pushOn.plungeMm, 10.0);
  EXPECT_TRUE(trained.stopped);
  EXPECT_LT(trained.plungeMm, pushOn.plungeMm / 2);
}

// The drilling scene at voxmap 128 (shell 512) in force mode, frames back to back, through the
// plate and 0.3 s past breakthrough: after breakthrough the drill's point creeps through the
// partial-volume remnant at the exit one sweep sub-step per frame, the sweep finding contact at
// its first sub-step. The proxy's fast path (ProxyOptions::sweepFirstContact: the sweep stops at
// the first point in contact, no candidate gathers) gives every frame of the reference path (a
// full contact query per sub-step) bit for bit: proxy and device positions, forces, feed, thrust,
// torque and removed voxels.
TEST(Breakthrough, TheFastPathsGiveTheReferenceFramesBitForBit) {
  bm::SceneOverrides ov;
  ov.voxmapResolution = 128;
  const bm::Scene scene = bm::ApplyOverrides(bm::ResolveScene("drilling"), ov);
  auto run = [&](bool fast) {
    bm::SessionRequest r;
    r.mode = bm::ScriptMode::Force;
    r.realTime = false;
    r.durationS = 2.0;
    bm::BuiltSession b = bm::BuildSession(scene, r);
    b.options.recordCapacity = 4000;
    b.options.proxy.sweepFirstContact = fast;
    bm::HapticSession session(*b.setup, b.device, b.options);
    session.Start();
    EXPECT_TRUE(session.WaitUntilPaused(600));
    session.Stop();
    std::vector<bm::FrameRecord> rec;
    session.DrainRecords(rec);
    return rec;
  };
  const std::vector<bm::FrameRecord> fast = run(true), reference = run(false);
  ASSERT_EQ(fast.size(), reference.size());
  ASSERT_EQ(fast.size(), 2000u);
  auto same = [](const auto& a, const auto& b) { // bit for bit (a -0.0 against 0.0 differs too)
    return std::memcmp(&a, &b, sizeof a) == 0;
  };
  int differing = 0, removing = 0, creeping = 0;
  const double h = 5.0 / 128; // the block's 5 mm over 128 voxels
  for (size_t k = 0; k < fast.size(); ++k) {
    const bm::FrameRecord &a = fast[k], &b = reference[k];
    const bool ok = same(a.devicePos, b.devicePos) && same(a.proxyPos, b.proxyPos) &&
                    same(a.feedMmPerRev, b.feedMmPerRev) && same(a.thrustN, b.thrustN) &&
                    same(a.torqueNmm, b.torqueNmm) && same(a.couplingForce, b.couplingForce) &&
                    same(a.deviceForce, b.deviceForce) && same(a.removedVoxels, b.removedVoxels) &&
                    same(a.removedVolumeMm3, b.removedVolumeMm3) && a.flags == b.flags;
    if (!ok && ++differing <= 3)
      ADD_FAILURE() << "frame " << k << " differs: proxy z " << a.proxyPos[2] << " against "
                    << b.proxyPos[2] << ", thrust " << a.thrustN << " against " << b.thrustN;
    removing += a.removedVoxels > 0;
    // A free advance stopped by the sweep's first contact: no thrust, about one sub-step deep.
    if (k > 0 && a.thrustN == 0) {
      const double step = fast[k - 1].proxyPos[2] - a.proxyPos[2];
      creeping += step > 0.4 * h && step < 0.51 * h;
    }
  }
  std::cout << "[fast paths] " << fast.size() << " frames, " << differing << " differing; "
            << removing << " removing, " << creeping
            << " advancing one sweep sub-step after breakthrough\n";
  EXPECT_EQ(differing, 0);
  // The run crosses breakthrough, where the sweep's first contact decides the advance.
  const bm::Breakthrough b =
      bm::MeasureBreakthrough(fast, [](const bm::FrameRecord& f) { return -f.proxyPos[2]; });
  EXPECT_TRUE(b.found);
  EXPECT_GT(removing, 50);
  EXPECT_GT(creeping, 10);
}

} // namespace
