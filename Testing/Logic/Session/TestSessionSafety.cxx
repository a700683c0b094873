// A session that is safe to pause and resume (Docs/Session.md, "Safety rules"): the overrun rule
// re-armed after a warm-up, a device moved while paused followed at bounded speed, a mouse depth
// step spread over frames, runaway pauses, and device faults that end the force at once.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>

#include "bmHapticSession.h"
#include "bmProgrammableDevice.h"
#include "bmScriptedDevice.h"
#include "bmSessionTestUtil.h"

namespace {

using bm::test::BurrScene;

bm::ScriptedDeviceOptions Plunge(double mmPerS) {
  bm::ScriptedDeviceOptions o;
  o.mode = bm::ScriptMode::Feed;
  o.startMm = {0, 0, 0.05};
  o.feedMmPerRev = mmPerS; // with speedRpm = 60: v = f n / 60 = f mm/s
  o.speedRpm = 60;
  return o;
}

// A scripted device whose every written force is logged (the session's output, as a device sees
// it).
class LoggingDevice final : public bm::Device {
public:
  explicit LoggingDevice(const bm::ScriptedDeviceOptions& o) : Inner_(o) {}
  std::string Name() const override { return "logging"; }
  bm::DeviceLimits Limits() const override { return Inner_.Limits(); }
  void Advance(double t, double dt) override { Inner_.Advance(t, dt); }
  bm::DeviceStatus Read(bm::DevicePose& p) override { return Inner_.Read(p); }
  bm::DeviceStatus Write(const Eigen::Vector3d& f) override {
    std::lock_guard<std::mutex> l(M_);
    Forces_.push_back(f);
    return Inner_.Write(f);
  }
  std::vector<Eigen::Vector3d> Forces() const {
    std::lock_guard<std::mutex> l(M_);
    return Forces_;
  }

private:
  bm::ScriptedDevice Inner_;
  mutable std::mutex M_;
  std::vector<Eigen::Vector3d> Forces_;
};

TEST(SessionSafety, ResumeReArmsTheOverrunRuleAfterAWarmUp) {
  const bm::Scene scene = BurrScene(0.5, {3, 3, 1.5}, 32, 64, 1000);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  bm::SessionOptions o;
  o.rateHz = 10000000; // a 0.1 us budget: every frame overruns
  o.overrunLimit = 5;
  o.overrunWindow = 100;
  o.resumeWarmupFrames = 40;
  o.startWarmupFrames = 0;
  bm::HapticSession session(setup, std::make_shared<bm::ScriptedDevice>(Plunge(0.5)), o);
  session.Start();
  ASSERT_TRUE(session.WaitUntilPaused(30.0));
  ASSERT_EQ(session.Snapshot().pauseReason, bm::PauseReason::Overrun);
  ASSERT_EQ(session.Snapshot().frame, 6);
  // Without the reset the full window paused again after one frame; now the warm-up's 40 frames
  // run and the 6th counted overrun after them pauses.
  ASSERT_TRUE(session.Resume());
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (session.Snapshot().frame == 6 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_TRUE(session.WaitUntilPaused(30.0));
  const bm::SessionSnapshot s = session.Snapshot();
  EXPECT_EQ(s.pauseReason, bm::PauseReason::Overrun);
  EXPECT_EQ(s.frame, 6 + 40 + 6);
  EXPECT_EQ(s.deviceForceN, Eigen::Vector3d::Zero());
  session.Stop();
  EXPECT_EQ(session.Timing().overruns, 52); // every frame still counts in the statistics
}

// Runs a burr cutting into a block with a mouse-driven device; while paused the device is moved
// `stepMm` deeper; returns the records after the resume.
struct ResumeRun {
  std::vector<bm::FrameRecord> before, after;
};
ResumeRun PauseMoveResume(const bm::SessionOptions& o, double stepMm, double mouseSpeedMmPerS) {
  const bm::Scene scene = BurrScene(0.5, {3, 3, 1.5}, 48, 64, 1000);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  // The panel's mouse proxy: a position source with a stiff coupling (2000 N/mm, 5000 N).
  bm::DeviceLimits stiff;
  stiff.maxForceN = 5000;
  stiff.maxStiffnessNPerMm = 2000;
  stiff.maxDampingNsPerMm = 2.0;
  stiff.workspaceRadiusMm = 1000;
  auto mouse = std::make_shared<bm::ProgrammableDevice>(stiff);
  bm::DevicePose p;
  mouse->SetMaxSpeed(mouseSpeedMmPerS);
  p.positionMm = {0, 0, 0.05};
  mouse->SetPose(p);
  bm::HapticSession session(setup, mouse, o);
  session.Start();
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (session.Snapshot().frame < 50 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  // Into the bone 0.1 mm, where the burr cuts and settles.
  p.positionMm = {0, 0, -0.1};
  mouse->SetPose(p);
  while (session.Snapshot().frame < 300 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  session.Pause();
  EXPECT_TRUE(session.WaitUntilPaused(5.0));
  ResumeRun r;
  session.DrainRecords(r.before);
  const int64_t paused = session.Snapshot().frame;
  p.positionMm = {0, 0, -0.1 - stepMm};
  mouse->SetPose(p);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_TRUE(session.Resume());
  while (session.Snapshot().frame < paused + 300 && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  session.Stop();
  session.DrainRecords(r.after);
  return r;
}

double MaxThrust(const std::vector<bm::FrameRecord>& v) {
  double m = 0;
  for (const auto& f : v)
    m = std::max(m, std::abs(f.thrustN));
  return m;
}
double MaxFeed(const std::vector<bm::FrameRecord>& v) {
  double m = 0;
  for (const auto& f : v)
    m = std::max(m, f.feedMmPerRev);
  return m;
}

TEST(SessionSafety, ADeviceMovedWhilePausedIsFollowedAtBoundedSpeedWithoutAForceSpike) {
  bm::SessionOptions o;
  o.overrunLimit = -1;
  o.catchUpSpeedMmPerS = 20;
  const ResumeRun now = PauseMoveResume(o, 1.0, 20.0); // the panel's mouse: 20 mm/s
  ASSERT_GT(now.before.size(), 100u);
  ASSERT_GT(now.after.size(), 100u);
  EXPECT_TRUE(now.after.front().flags & bm::FrameRecord::kResumed);
  // The target the proxy follows walks from the proxy toward the device at <= 20 mm/s (0.02 mm
  // per frame), and the proxy never jumps.
  Eigen::Vector3d prevTarget(now.before.back().proxyPos[0], now.before.back().proxyPos[1],
                             now.before.back().proxyPos[2]);
  Eigen::Vector3d prevProxy = prevTarget;
  double maxTargetStep = 0, maxProxyStep = 0;
  for (const auto& f : now.after) {
    const Eigen::Vector3d t(f.devicePos[0], f.devicePos[1], f.devicePos[2]);
    const Eigen::Vector3d q(f.proxyPos[0], f.proxyPos[1], f.proxyPos[2]);
    maxTargetStep = std::max(maxTargetStep, (t - prevTarget).norm());
    maxProxyStep = std::max(maxProxyStep, (q - prevProxy).norm());
    prevTarget = t;
    prevProxy = q;
  }
  EXPECT_LE(maxTargetStep, 0.02 + 1e-9);
  EXPECT_LE(maxProxyStep, 0.02 + 1e-9);
  // No frame cuts faster than the force model's largest feed (1 mm/rev), before or after.
  EXPECT_LE(MaxFeed(now.before), 1.0 + 1e-9);
  EXPECT_LE(MaxFeed(now.after), 1.0 + 1e-9);
  EXPECT_GT(MaxThrust(now.before), 0.0); // it did cut
  // The old behaviour, for comparison: the step in one frame, an unslewed mouse, any feed.
  bm::SessionOptions old = o;
  old.catchUpSpeedMmPerS = 0;
  old.proxy.maxFeedMmPerRev = 1e30;
  const ResumeRun was = PauseMoveResume(old, 1.0, 0.0);
  std::cout << "[resume] stiff mouse proxy (2000 N/mm), 1 mm deeper while paused: max feed "
            << MaxFeed(now.after) << " mm/rev, thrust " << MaxThrust(now.after)
            << " N (without the catch-up, slew and feed bound: feed " << MaxFeed(was.after)
            << " mm/rev, thrust " << MaxThrust(was.after) << " N); largest target step "
            << maxTargetStep << " mm, proxy step " << maxProxyStep << " mm\n";
  EXPECT_GT(MaxFeed(was.after), 1.5); // half a voxel in a frame: the spikes the bounds remove
}

TEST(SessionSafety, AMouseDepthStepIsSpreadOverFrames) {
  bm::ProgrammableDevice mouse;
  mouse.SetMaxSpeed(10); // mm/s: 0.01 mm per 1 ms frame
  bm::DevicePose p, got;
  p.positionMm = {1, 2, 3};
  mouse.SetPose(p);
  mouse.Advance(0, 0.001);
  ASSERT_EQ(mouse.Read(got), bm::DeviceStatus::Ok);
  EXPECT_EQ(got.positionMm, p.positionMm); // the first pose as it is
  p.positionMm(2) -= 0.1;                  // a wheel click: 0.1 mm deeper
  mouse.SetPose(p);
  int frames = 0;
  double prev = 3;
  while (got.positionMm(2) > 2.9 + 1e-12 && frames < 100) {
    mouse.Advance(0.001 * frames, 0.001);
    mouse.Read(got);
    EXPECT_LE(prev - got.positionMm(2), 0.01 + 1e-12);
    prev = got.positionMm(2);
    ++frames;
  }
  EXPECT_EQ(frames, 10);
  EXPECT_NEAR(got.positionMm(2), 2.9, 1e-12);
  mouse.SetMaxSpeed(0); // no limit: the next pose at once
  p.positionMm(2) = 0;
  mouse.SetPose(p);
  mouse.Read(got);
  EXPECT_EQ(got.positionMm(2), 0.0);
}

TEST(SessionSafety, ARunawayPausesWithItsOwnReason) {
  const bm::Scene scene = BurrScene(0.5, {3, 3, 1.5}, 32, 64, 1000);
  bm::SessionOptions o;
  o.realTime = false;
  o.overrunLimit = -1;
  o.maxFrames = 5000;
  o.speedRpm = 0; // spindle stopped: the bone is rigid
  // A device driven 100 mm into the bone in 1 s: the proxy stays on the bone's face, the device
  // ends far below it.
  {
    bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
    bm::ScriptedDeviceOptions d;
    d.mode = bm::ScriptMode::Trajectory;
    d.trajectory = {{0.0, {0, 0, 0.05}, Eigen::Matrix3d::Identity(), 0},
                    {1.0, {0, 0, -100}, Eigen::Matrix3d::Identity(), 0}};
    bm::HapticSession session(setup, std::make_shared<bm::ScriptedDevice>(d), o);
    session.Start();
    ASSERT_TRUE(session.WaitUntilPaused(60));
    const bm::SessionSnapshot s = session.Snapshot();
    EXPECT_EQ(s.pauseReason, bm::PauseReason::Runaway);
    EXPECT_EQ(s.deviceForceN, Eigen::Vector3d::Zero());
    EXPECT_GT((s.devicePositionMm - s.proxyPositionMm).norm(), 50.0);
    EXPECT_LT(s.frame, 600); // 50 mm at 100 mm/s, and not much later
    EXPECT_STREQ(bm::ToString(s.pauseReason), "runaway");
    session.Stop();
  }
  // A device that carries the tool 1 m away in free space: out of the bone's region.
  {
    bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
    bm::ScriptedDeviceOptions d;
    d.mode = bm::ScriptMode::Trajectory;
    d.trajectory = {{0.0, {0, 0, 1}, Eigen::Matrix3d::Identity(), 0},
                    {2.0, {1000, 0, 1}, Eigen::Matrix3d::Identity(), 0}};
    bm::HapticSession session(setup, std::make_shared<bm::ScriptedDevice>(d), o);
    session.Start();
    ASSERT_TRUE(session.WaitUntilPaused(60));
    const bm::SessionSnapshot s = session.Snapshot();
    EXPECT_EQ(s.pauseReason, bm::PauseReason::Runaway);
    EXPECT_NEAR(s.proxyPositionMm(0), 151.5, 1.0); // the block's 1.5 mm half width + 150 mm
    session.Stop();
  }
}

TEST(SessionSafety, ANonFinitePoseIsADeviceFaultWithZeroForceAndNoForceAfterIt) {
  const bm::Scene scene = BurrScene(0.5, {3, 3, 1.5}, 32, 64, 0);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  bm::ScriptedDeviceOptions d;
  d.mode = bm::ScriptMode::Trajectory; // pressed 0.3 mm into the bone (rigid), then a NaN sample
  d.trajectory = {{0.0, {0, 0, -0.3}, Eigen::Matrix3d::Identity(), 0},
                  {0.1, {0, 0, -0.3}, Eigen::Matrix3d::Identity(), 0},
                  {0.2, {0, nan, -0.3}, Eigen::Matrix3d::Identity(), 0}};
  auto dev = std::make_shared<LoggingDevice>(d);
  bm::SessionOptions o;
  o.realTime = false;
  o.overrunLimit = -1;
  o.speedRpm = 0;
  bm::HapticSession session(setup, dev, o);
  session.Start();
  ASSERT_TRUE(session.WaitUntilPaused(60));
  const bm::SessionSnapshot s = session.Snapshot();
  EXPECT_EQ(s.pauseReason, bm::PauseReason::DeviceError);
  EXPECT_EQ(s.frame, 100); // the frame at t = 0.1 s, the first with a NaN pose, ran no physics
  const auto forces = dev->Forces();
  ASSERT_GE(forces.size(), 101u);
  EXPECT_GT(forces[99].norm(), 0.05);              // the bone pushed back until then
  EXPECT_EQ(forces[100], Eigen::Vector3d::Zero()); // zero in the faulting frame itself
  // A device error is final: no resume, and nothing but zero force from here on.
  EXPECT_FALSE(session.Resume());
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(session.Snapshot().state, bm::SessionState::Paused);
  EXPECT_EQ(session.Snapshot().frame, 100);
  session.Stop();
  const auto all = dev->Forces();
  for (size_t i = 100; i < all.size(); ++i)
    EXPECT_EQ(all[i], Eigen::Vector3d::Zero()) << "write " << i;
}

} // namespace
