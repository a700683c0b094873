// The session thread: start/pause/resume/stop, snapshots read concurrently (this file runs under
// ThreadSanitizer in CI), timing statistics, the safety pauses, and the force-mode drilling run.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "bmHapticSession.h"
#include "bmProgrammableDevice.h"
#include "bmScriptedDevice.h"
#include "bmSessionTestUtil.h"

namespace {

using bm::test::BurrScene;

bm::ScriptedDeviceOptions PlungeOptions(double speedMmPerS) {
  bm::ScriptedDeviceOptions o;
  o.mode = bm::ScriptMode::Feed;
  o.startMm = {0, 0, 0.05};
  o.feedMmPerRev = speedMmPerS; // with speedRpm = 60: v = f n / 60 = f mm/s
  o.speedRpm = 60;
  return o;
}

TEST(HapticSession, StartPauseResumeStopWithConcurrentSnapshotReaders) {
  const bm::Scene scene = BurrScene(0.5, {3, 3, 1.5}, 48, 64, 1000);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  auto dev = std::make_shared<bm::ScriptedDevice>(PlungeOptions(0.5));
  bm::SessionOptions o;
  o.overrunLimit = -1;
  bm::HapticSession session(setup, dev, o);
  EXPECT_EQ(session.Snapshot().state, bm::SessionState::Idle);
  std::atomic<bool> stop{false};
  std::atomic<int64_t> reads{0}, lastFrame{0};
  std::atomic<bool> monotone{true};
  std::thread gui([&] {
    while (!stop.load()) {
      const bm::SessionSnapshot s = session.Snapshot();
      if (s.frame < lastFrame.load())
        monotone = false;
      lastFrame = s.frame;
      ++reads;
    }
  });
  // Waits (at most 10 s) until the session has run frame n: a loaded CI machine may not
  // schedule the haptic thread for a fixed sleep's worth of frames.
  auto waitForFrame = [&](int64_t n) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (session.Snapshot().frame < n && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return session.Snapshot().frame >= n;
  };
  session.Start();
  EXPECT_THROW(session.Start(), std::logic_error);
  ASSERT_TRUE(waitForFrame(120));
  session.Pause();
  ASSERT_TRUE(session.WaitUntilPaused(2.0));
  const bm::SessionSnapshot p1 = session.Snapshot();
  EXPECT_EQ(p1.state, bm::SessionState::Paused);
  EXPECT_EQ(p1.pauseReason, bm::PauseReason::User);
  EXPECT_EQ(p1.deviceForceN, Eigen::Vector3d::Zero());
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  EXPECT_EQ(session.Snapshot().frame, p1.frame); // no frames while paused
  EXPECT_THROW(session.SetDevice(std::make_shared<bm::ProgrammableDevice>()), std::logic_error);
  session.Resume();
  ASSERT_TRUE(waitForFrame(p1.frame + 50));
  const bm::SessionSnapshot r = session.Snapshot();
  EXPECT_EQ(r.state, bm::SessionState::Running);
  EXPECT_GT(r.frame, p1.frame);
  session.Stop();
  session.Stop(); // idempotent
  stop = true;
  gui.join();
  EXPECT_TRUE(monotone.load());
  EXPECT_GT(reads.load(), 10);
  const bm::TimingStats t = session.Timing();
  EXPECT_GT(t.frames, 100);
  EXPECT_GT(t.p50Ms, 0.0);
  EXPECT_LE(t.p50Ms, t.p99Ms);
  EXPECT_LE(t.p99Ms, t.maxMs + 1e-3);
  EXPECT_EQ(session.Snapshot().state, bm::SessionState::Stopped);
  std::vector<bm::FrameRecord> rec;
  session.DrainRecords(rec);
  EXPECT_EQ(int64_t(rec.size()), t.frames);
  int resumed = 0;
  for (const auto& f : rec)
    resumed += (f.flags & bm::FrameRecord::kResumed) ? 1 : 0;
  EXPECT_EQ(resumed, 1);
  std::cout << "[session] " << t.frames << " frames, p50 " << t.p50Ms << " ms, p99 " << t.p99Ms
            << " ms, max " << t.maxMs << " ms, overruns " << t.overruns << ", snapshot reads "
            << reads.load() << "\n";
}

TEST(HapticSession, DeviceFaultsRampTheForceToZeroAndPauseKeepingTheCut) {
  const bm::Scene scene = BurrScene(0.5, {3, 3, 1.5}, 48, 64, 1000);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  const double boneBefore = setup.Bone().BoneVolume();
  bm::ScriptedDeviceOptions so = PlungeOptions(2.0); // 2 mm/s into the bone
  so.errorAtS = 0.25;
  auto dev = std::make_shared<bm::ScriptedDevice>(so);
  bm::SessionOptions o;
  o.realTime = false;
  o.overrunLimit = -1;
  bm::HapticSession session(setup, dev, o);
  session.Start();
  ASSERT_TRUE(session.WaitUntilPaused(60.0));
  const bm::SessionSnapshot s = session.Snapshot();
  EXPECT_EQ(s.pauseReason, bm::PauseReason::DeviceError);
  EXPECT_EQ(s.deviceForceN, Eigen::Vector3d::Zero());
  EXPECT_EQ(s.frame, 250);
  session.Stop();
  EXPECT_GT(s.removedVolumeMm3, 0.0);
  EXPECT_NEAR(setup.Bone().BoneVolume(), boneBefore - s.removedVolumeMm3, 1e-6); // the cut is kept
  // A device that stops answering pauses the session as well.
  bm::MachiningSetup setup2(scene, bm::MakeSceneBlock(scene));
  so.errorAtS = -1;
  so.silentAtS = 0.1;
  bm::HapticSession silent(setup2, std::make_shared<bm::ScriptedDevice>(so), o);
  silent.Start();
  ASSERT_TRUE(silent.WaitUntilPaused(60.0));
  EXPECT_EQ(silent.Snapshot().pauseReason, bm::PauseReason::DeviceSilent);
  silent.Stop();
}

/// Session options under which every frame overruns (a 0.1 us budget), with the default rule
/// (more than 5 of 100 frames) and `startWarmupFrames` frames after Start not counted.
bm::SessionOptions EveryFrameOverruns(int startWarmupFrames) {
  bm::SessionOptions o;
  o.rateHz = 10000000;
  o.overrunLimit = 5;
  o.overrunWindow = 100;
  o.startWarmupFrames = startWarmupFrames;
  return o;
}

TEST(HapticSession, RepeatedOverrunsPauseTheSession) {
  const bm::Scene scene = BurrScene(0.5, {3, 3, 1.5}, 48, 64, 1000);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  const bm::SessionOptions o = EveryFrameOverruns(0);
  bm::HapticSession session(setup, std::make_shared<bm::ScriptedDevice>(PlungeOptions(0.5)), o);
  session.Start();
  ASSERT_TRUE(session.WaitUntilPaused(30.0));
  const bm::SessionSnapshot s = session.Snapshot();
  EXPECT_EQ(s.pauseReason, bm::PauseReason::Overrun);
  EXPECT_EQ(s.frame, 6); // paused at the 6th overrun, not later
  EXPECT_EQ(s.deviceForceN, Eigen::Vector3d::Zero());
  session.Stop();
  EXPECT_EQ(session.Timing().overruns, 6);
}

// The first frames after Start (thread start, cold caches, the view's first extraction) do not
// count toward the rule: with a 30-frame start warm-up the 6th counted overrun is frame 36.
TEST(HapticSession, StartWarmUpFramesDoNotCountTowardTheOverrunRule) {
  const bm::Scene scene = BurrScene(0.5, {3, 3, 1.5}, 48, 64, 1000);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  const bm::SessionOptions o = EveryFrameOverruns(30);
  bm::HapticSession session(setup, std::make_shared<bm::ScriptedDevice>(PlungeOptions(0.5)), o);
  session.Start();
  ASSERT_TRUE(session.WaitUntilPaused(30.0));
  EXPECT_EQ(session.Snapshot().pauseReason, bm::PauseReason::Overrun);
  EXPECT_EQ(session.Snapshot().frame, 36);
  session.Stop();
  EXPECT_EQ(session.Timing().overruns, 36); // every frame still counts in the statistics
}

TEST(HapticSession, ForceModeDrillingFeedsWhereThrustBalancesTheAppliedForce) {
  // The reference drill pushed with 2 N by a force-controlled robot (Touch limits): once drilling,
  // the rendered force carries the 2 N, the proxy advances at the feed whose thrust balances it.
  const bm::Scene scene = bm::test::DrillScene({3, 3, 1.0}, 96, 256);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  bm::ScriptedDeviceOptions so;
  so.mode = bm::ScriptMode::Force;
  so.startMm = {0, 0, 0.02};
  so.appliedForceN = 2.0;
  so.rotation = setup.ToolRotation();
  bm::SessionOptions o;
  o.realTime = false;
  o.overrunLimit = -1;
  o.maxFrames = 700;
  bm::HapticSession session(setup, std::make_shared<bm::ScriptedDevice>(so), o);
  session.Start();
  ASSERT_TRUE(session.WaitUntilPaused(120.0));
  EXPECT_EQ(session.Snapshot().pauseReason, bm::PauseReason::Finished);
  session.Stop();
  std::vector<bm::FrameRecord> rec;
  session.DrainRecords(rec);
  ASSERT_EQ(rec.size(), 700u);
  std::vector<double> thrust, force;
  for (size_t i = 400; i < rec.size(); ++i) {
    thrust.push_back(rec[i].thrustN);
    force.push_back(rec[i].deviceForce[2]); // up: the bone holds the hand's push
  }
  const auto [mT, rT] = bm::test::MeanRipple(thrust, 0, thrust.size());
  const auto [mF, rF] = bm::test::MeanRipple(force, 0, force.size());
  EXPECT_NEAR(mF, 2.0, 0.15); // the robot's push, carried by the coupling
  EXPECT_NEAR(mT, mF, 0.2);   // the thrust balances it
  EXPECT_GT(rec.back().feedMmPerRev, 0.0);
  EXPECT_LT(rec.back().proxyPos[2], 0.0); // drilling into the block
  for (const auto& f : rec)
    ASSERT_LE(std::hypot(f.deviceForce[0], f.deviceForce[1], f.deviceForce[2]), 3.3);
  std::cout << "[force mode] applied 2 N: device force " << mF << " N (ripple " << rF
            << "), thrust " << mT << " N (ripple " << rT << "), feed " << rec.back().feedMmPerRev
            << " mm/rev, depth " << -rec.back().proxyPos[2] << " mm\n";
}

} // namespace
