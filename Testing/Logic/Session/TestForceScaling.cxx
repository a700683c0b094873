// Force scaling (tool force = s x device force) and the scripted hand (Docs/Session.md).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "bmHapticSession.h"
#include "bmReplay.h"
#include "bmScriptedDevice.h"
#include "bmSessionRecorder.h"
#include "bmSessionTestUtil.h"
#include "bmVirtualCoupling.h"

namespace {

TEST(ForceScaling, TheCouplingCarriesSTimesTheDeviceForceAndTheHandFeelsTheSameSpring) {
  const bm::DeviceLimits touch;
  bm::CouplingOptions o;
  const bm::VirtualCoupling one(o, touch, 0.001);
  o.forceScale = 20;
  const bm::VirtualCoupling c(o, touch, 0.001);
  EXPECT_DOUBLE_EQ(c.Stiffness(), 20 * one.Stiffness()); // 8 N/mm on the tool side
  EXPECT_DOUBLE_EQ(c.Damping(), 20 * one.Damping());
  EXPECT_DOUBLE_EQ(c.MaxForce(), 20 * 3.3);
  EXPECT_DOUBLE_EQ(c.DeviceMaxForce(), 3.3);
  EXPECT_DOUBLE_EQ(c.ForceScale(), 20);
  // 1 mm of stretch: 8 N on the tool, 0.4 N at the hand, as without scaling.
  const Eigen::Vector3d f = c.Force({0, 0, -1}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                    Eigen::Vector3d::Zero());
  EXPECT_NEAR(f(2), -8.0, 1e-12);
  EXPECT_NEAR(c.DeviceForce(f)(2), 0.4, 1e-12);
  EXPECT_NEAR(one.DeviceForce(one.Force({0, 0, -1}, Eigen::Vector3d::Zero(),
                                        Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()))(2),
              0.4, 1e-12);
  // 100 N on the tool is 5 N at the device: clamped to the Touch's 3.3 N.
  EXPECT_NEAR(c.DeviceForce({0, 0, -100}).norm(), 3.3, 1e-9);
  for (double bad : {0.0, -1.0, 2000.0, std::numeric_limits<double>::quiet_NaN()}) {
    o.forceScale = bad;
    try {
      bm::VirtualCoupling x(o, touch, 0.001);
      ADD_FAILURE() << "force scale " << bad << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("[0.001, 1000]"), std::string::npos) << e.what();
    }
  }
}

// The reference drill pushed by a force-controlled hand at 1.5 N: the tool's thrust is s times
// the device force that carries the push.
std::pair<double, double> DrillPush(double scale, std::vector<bm::FrameRecord>* out = nullptr,
                                    bm::ScriptMode mode = bm::ScriptMode::Force,
                                    bm::SessionOptions* used = nullptr) {
  const bm::Scene scene = bm::test::DrillScene({3, 3, 1.0}, 64, 192);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  bm::ScriptedDeviceOptions so;
  so.mode = mode;
  so.startMm = {0, 0, 0.02};
  so.appliedForceN = 1.5;
  so.handRampS = 0.1;
  so.rotation = setup.ToolRotation();
  bm::SessionOptions o;
  o.realTime = false;
  o.overrunLimit = -1;
  o.maxFrames = 600;
  o.proxy.coupling.forceScale = scale;
  bm::HapticSession session(setup, std::make_shared<bm::ScriptedDevice>(so), o);
  session.Start();
  EXPECT_TRUE(session.WaitUntilPaused(120.0));
  EXPECT_EQ(session.Snapshot().pauseReason, bm::PauseReason::Finished);
  session.Stop();
  std::vector<bm::FrameRecord> rec;
  session.DrainRecords(rec);
  EXPECT_EQ(rec.size(), 600u);
  std::vector<double> thrust, force;
  for (size_t i = 350; i < rec.size(); ++i) {
    thrust.push_back(rec[i].thrustN);
    force.push_back(rec[i].deviceForce[2]);
  }
  for (const auto& f : rec)
    EXPECT_LE(std::hypot(f.deviceForce[0], f.deviceForce[1], f.deviceForce[2]), 3.3);
  if (out)
    *out = rec;
  if (used)
    *used = o;
  return {bm::test::MeanRipple(thrust, 0, thrust.size()).first,
          bm::test::MeanRipple(force, 0, force.size()).first};
}

TEST(ForceScaling, AForceModeSessionDrillsWithSTimesTheHandsPush) {
  const auto [thrust1, device1] = DrillPush(1.0);
  const auto [thrust8, device8] = DrillPush(8.0);
  std::cout << "[force scale] 1.5 N push: scale 1 thrust " << thrust1 << " N (device " << device1
            << " N); scale 8 thrust " << thrust8 << " N (device " << device8 << " N)\n";
  EXPECT_NEAR(device1, 1.5, 0.15);
  EXPECT_NEAR(device8, 1.5, 0.15);
  EXPECT_NEAR(thrust1, 1.5, 0.25);
  EXPECT_NEAR(thrust8, 8 * 1.5, 8 * 0.25); // the tool pushes 12 N for the hand's 1.5 N
}

TEST(ScriptedHand, APushWithinTheDevicesRangeAndASeededLateralTremor) {
  bm::ScriptedDeviceOptions o;
  o.mode = bm::ScriptMode::Hand;
  o.axis = {0, 0, 1};
  o.appliedForceN = 3.2; // close to the Touch's 3.3 N: the waver and tremor must stay under it
  o.handTremorN = 0.15;
  o.handSeed = 7;
  const bm::ScriptedDevice a(o), b(o);
  o.handSeed = 8;
  const bm::ScriptedDevice c(o);
  double maxN = 0, maxLateral = 0, differs = 0, lateralAt1s = 0;
  for (int k = 0; k <= 3000; ++k) {
    const double t = 0.001 * k;
    const Eigen::Vector3d fa = a.HandForce(t);
    EXPECT_EQ(fa, b.HandForce(t)); // the same seed, the same hand
    differs = std::max(differs, (fa - c.HandForce(t)).norm());
    maxN = std::max(maxN, fa.norm());
    maxLateral = std::max(maxLateral, std::hypot(fa(0), fa(1)));
    if (k == 1000)
      lateralAt1s = std::hypot(fa(0), fa(1));
  }
  EXPECT_EQ(a.HandForce(0).norm(), 0.0); // the push starts from nothing
  EXPECT_LE(maxN, 3.3);                  // within the device's maximum force
  EXPECT_GT(maxN, 3.2);                  // and reaches the firm push
  EXPECT_GT(maxLateral, 0.05);           // a tremor across the axis
  EXPECT_LT(maxLateral, 2 * 0.15 + 1e-12);
  EXPECT_GT(differs, 0.01); // another seed, another tremor
  EXPECT_GE(lateralAt1s, 0.0);
  // A push beyond the device's range is refused, naming the range.
  o.appliedForceN = 4.0;
  try {
    bm::ScriptedDevice d(o);
    ADD_FAILURE() << "4 N accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("[0, 3.3]"), std::string::npos) << e.what();
  }
  o.mode = bm::ScriptMode::Force;
  EXPECT_THROW(bm::ScriptedDevice{o}, std::invalid_argument);
}

TEST(ScriptedHand, AHandDrivenScaledSessionIsRecordedWithItsScaleAndReplaysExactly) {
  std::vector<bm::FrameRecord> frames;
  bm::SessionOptions o;
  const auto [thrust, device] = DrillPush(8.0, &frames, bm::ScriptMode::Hand, &o);
  std::cout << "[scripted hand] 1.5 N hand at scale 8: thrust " << thrust << " N, device force "
            << device << " N\n";
  EXPECT_NEAR(thrust, 8 * device, 8 * 0.3);
  // Lateral tremor reaches the device's force too (the bone holds the tool across the axis).
  double lateral = 0;
  for (const auto& f : frames)
    lateral = std::max(lateral, std::hypot(f.deviceForce[0], f.deviceForce[1]));
  EXPECT_GT(lateral, 0.0);
  bm::Recording rec;
  rec.frames = frames;
  rec.meta = {{"scene", bm::test::DrillScene({3, 3, 1.0}, 64, 192).ToJson()},
              {"session", bm::SessionOptionsToJson(o, bm::DeviceLimits{})}};
  EXPECT_EQ(rec.meta["session"]["force_scale"].get<double>(), 8.0);
  const bm::Scene scene = bm::RecordedScene(rec);
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  const bm::ReplayResult r = bm::Replay(rec, setup);
  EXPECT_EQ(r.frames, 600);
  EXPECT_EQ(r.maxCouplingForceDiffN, 0.0);
  EXPECT_EQ(r.maxThrustDiffN, 0.0);
  EXPECT_EQ(r.maxDeviceForceDiffN, 0.0);
  // A recording that cannot be replayed is refused, naming the frame and the field.
  rec.frames[3].devicePos[1] = std::numeric_limits<double>::infinity();
  try {
    bm::Replay(rec, setup);
    ADD_FAILURE() << "an infinite pose was replayed";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "frame 3 of the recording has a non-finite device position");
  }
  rec.frames.clear();
  EXPECT_THROW(bm::CheckReplayable(rec), std::runtime_error);
}

} // namespace
