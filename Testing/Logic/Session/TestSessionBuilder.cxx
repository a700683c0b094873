// The one way to build a session (bmSessionBuilder.h) and a scene's overrides
// (bmSceneOverrides.h): the command line's and the BM Session source's requests start the tool
// at the same pose and run the same frames; bad overrides and requests are refused by name.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "bmEdgeQuadrature.h"
#include "bmFeedBalance.h"
#include "bmToolModel.h"
#include "bmSessionBenchTable.h"
#include "bmSceneBone.h"
#include "bmSceneOverrides.h"
#include "bmSessionBuilder.h"
#include "bmVirtualCoupling.h"

namespace {

/// The drilling scene at voxmap 32 (shell 128): small enough to build in milliseconds.
bm::Scene SmallDrilling() {
  bm::SceneOverrides o;
  o.voxmapResolution = 32;
  return bm::ApplyOverrides(bm::ResolveScene("drilling"), o);
}

/// The message of the std::invalid_argument that f throws ("" when it throws none).
template <class F> std::string Refusal(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

bm::DevicePose StartPose(const bm::BuiltSession& b) {
  auto* scripted = dynamic_cast<bm::ScriptedDevice*>(b.device.get());
  EXPECT_NE(scripted, nullptr);
  return scripted ? scripted->PoseAt(0) : bm::DevicePose();
}

TEST(SceneOverrides, VoxmapAloneScalesTheShellAndKeepsTheBaseDir) {
  const bm::Scene base = bm::ResolveScene("drilling");
  bm::SceneOverrides o;
  o.voxmapResolution = 64;
  const bm::Scene s = bm::ApplyOverrides(base, o);
  EXPECT_EQ(s.voxmapResolution, 64);
  EXPECT_EQ(s.shellResolution, base.shellResolution * 64 / base.voxmapResolution);
  EXPECT_EQ(s.baseDir, base.baseDir);
  o.shellResolution = 100;
  const bm::Scene both = bm::ApplyOverrides(base, o);
  EXPECT_EQ(both.voxmapResolution, 64);
  EXPECT_EQ(both.shellResolution, 100);
}

TEST(SceneOverrides, TrialToolAndMethodReplaceTheScenes) {
  bm::SceneOverrides o;
  o.entryMm = Eigen::Vector3d(1, 2, 3);
  o.axis = Eigen::Vector3d(0, 0, 2);
  o.feedMmPerRev = 0.05;
  o.speedRpm = 600;
  o.toolJson = R"({"type": "drill", "radius_mm": 2.0})";
  o.method = "zheng";
  const bm::Scene s = bm::ApplyOverrides(bm::ResolveScene("drilling"), o);
  EXPECT_EQ(s.trial.entry, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(s.trial.axis, Eigen::Vector3d(0, 0, 1)); // normalised
  EXPECT_DOUBLE_EQ(s.trial.feedMmPerRev, 0.05);
  EXPECT_DOUBLE_EQ(s.trial.speedRpm, 600);
  EXPECT_DOUBLE_EQ(s.tool.at("radius_mm").get<double>(), 2.0);
  EXPECT_EQ(s.ToJson().at("method"), "zheng");
}

TEST(SceneOverrides, BadOverridesAreRefusedByName) {
  const bm::Scene base = bm::ResolveScene("drilling");
  auto refusal = [&](const bm::SceneOverrides& o) {
    return Refusal([&] { bm::ApplyOverrides(base, o); });
  };
  bm::SceneOverrides o;
  o.voxmapResolution = 4;
  EXPECT_NE(refusal(o).find("voxmap resolution (cells) must be in [8, 4096], not 4"),
            std::string::npos)
      << refusal(o);
  o = {};
  o.shellResolution = 5000;
  EXPECT_NE(refusal(o).find("shell resolution (cells) must be in [8, 4096]"), std::string::npos);
  o = {};
  o.toolJson = "{radius";
  EXPECT_NE(refusal(o).find("the tool specification is not JSON"), std::string::npos);
  o.toolJson = "[1, 2]";
  EXPECT_NE(refusal(o).find("the tool specification must be a JSON object"), std::string::npos);
  // Nested 100 000 deep: refused at the depth limit instead of overflowing the stack.
  o.toolJson = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_NE(refusal(o).find("is nested deeper than 64"), std::string::npos) << refusal(o);
  o = {};
  o.method = "euler";
  EXPECT_NE(refusal(o).find("lazar or zheng, not 'euler'"), std::string::npos);
  o = {};
  o.boneFile = "a.nrrd";
  o.boneCTJson = R"({"ct": "x"})";
  EXPECT_NE(refusal(o).find("not both"), std::string::npos);
  o = {};
  o.boneCTJson = R"({"threshold": 300})";
  EXPECT_NE(refusal(o).find("with \"ct\""), std::string::npos);
  o = {};
  o.entryMm = Eigen::Vector3d(0, 0, 0);
  EXPECT_NE(refusal(o).find("both an entry point and an axis"), std::string::npos);
  o.axis = Eigen::Vector3d::Zero();
  EXPECT_NE(refusal(o).find("axis must be finite and non-zero"), std::string::npos);
  o = {};
  o.feedMmPerRev = 2.0;
  EXPECT_NE(refusal(o).find("the feed (mm/rev) must be in [1e-05, 1], not 2"), std::string::npos)
      << refusal(o);
  o = {};
  o.threads = 0;
  EXPECT_NE(refusal(o).find("thread count must be in [1, 64]"), std::string::npos);
  EXPECT_NE(Refusal([] { bm::ResolveScene("no-such-scene"); }).find("no-such-scene"),
            std::string::npos);
  bm::SceneOverrides missing;
  missing.boneFile = "/nonexistent/cut.nrrd";
  EXPECT_THROW(bm::ApplyOverrides(base, missing), std::runtime_error);
}

TEST(SessionBuilder, CommandLineAndSourceFeedsStartAtTheSamePoseAndRunTheSameFrames) {
  const bm::Scene scene = SmallDrilling();
  bm::SessionRequest cli; // bmsim run --device scripted (--mode feed)
  bm::SessionRequest source;
  source.device = bm::SessionDevice::Robot; // the BM Session source's "Scripted robot"
  source.realTime = false;
  const bm::BuiltSession a = bm::BuildSession(scene, cli);
  const bm::BuiltSession b = bm::BuildSession(scene, source);
  const bm::DevicePose pa = StartPose(a), pb = StartPose(b);
  EXPECT_TRUE(pa.positionMm.isApprox(pb.positionMm, 1e-12));
  EXPECT_TRUE(pa.rotation.isApprox(pb.rotation, 1e-12));
  // The foremost cutting point starts the trial's clearance above the entry, as the feed trial.
  const bm::TrialSpec& t = a.setup->GetScene().trial;
  EXPECT_NEAR(bm::ToolDepthMm(*a.setup, pa.positionMm, pa.rotation), -t.clearanceMm, 1e-12);
  // Both run to the trial's depth at its feed rate.
  const double depth = bm::FullEngagementDepth(a.setup->Tool()) + t.extraDepthMm;
  EXPECT_NEAR(bm::TrialDepthMm(*a.setup), depth, 1e-12);
  const double seconds = (depth + t.clearanceMm) / (t.feedMmPerRev * t.speedRpm / 60.0);
  EXPECT_EQ(a.options.maxFrames, int64_t(std::ceil(seconds * 1000)));
  EXPECT_EQ(b.options.maxFrames, a.options.maxFrames);
  EXPECT_NEAR(a.durationS, seconds, 1e-9);
  // They differ where the devices do: a hand on a Touch against a stiff robot arm.
  EXPECT_DOUBLE_EQ(a.options.proxy.coupling.forceScale, bm::SessionForceScale(*a.setup));
  EXPECT_DOUBLE_EQ(b.options.proxy.coupling.forceScale, 1.0);
  EXPECT_DOUBLE_EQ(a.device->Limits().maxForceN, bm::DeviceLimits().maxForceN);
  EXPECT_DOUBLE_EQ(b.device->Limits().maxForceN, bm::PositionSourceLimits().maxForceN);
  EXPECT_EQ(a.options.overrunLimit, -1); // a scripted run reports overruns, never pauses on them
  EXPECT_EQ(b.options.overrunLimit, -1);
}

TEST(SessionBuilder, AChosenGridFollowsTheMeasurementsAndTheCTsSpacing) {
  // Not chosen: the scene's, whatever the table says.
  bm::SessionRequest req;
  req.realTime = false;
  req.maxFrames = 1;
  bm::BuiltSession b = bm::BuildSession(SmallDrilling(), req);
  EXPECT_EQ(b.setup->GetScene().voxmapResolution, 32);
  EXPECT_TRUE(b.gridReason.empty());
  if (!bm::CanImportSceneBones())
    GTEST_SKIP() << "built without CT import: the glenoid's grid cannot be chosen";

  // A session table where voxmap 128 holds 1 kHz with one engine thread and 192 does not.
  const std::filesystem::path table =
      std::filesystem::temp_directory_path() / ("bm-grid-" + std::to_string(::getpid()) + ".csv");
  auto row = [](int voxmap, int threads, double p99) {
    bm::SessionBenchRow r;
    r.scene = "glenoid";
    r.voxmap = voxmap;
    r.shell = voxmap * 340 / 192;
    r.threads = threads;
    r.path = "incremental";
    r.run = 1;
    r.frames = 1000;
    r.p50Ms = p99 / 2;
    r.p99Ms = p99;
    r.seconds = 1;
    r.machine = "test machine";
    r.date = "2026-11-26";
    return bm::SessionBenchCsvRecord(r) + "\n";
  };
  auto write = [&](const std::string& rows) {
    std::ofstream(table) << bm::SessionBenchCsvHeader() << "\n" << rows;
  };
  ::setenv("BM_SESSION_BENCHMARK_CSV", table.c_str(), 1);
  req.chooseGrid = true;
  const bm::Scene glenoid = bm::ResolveScene("glenoid");
  ASSERT_EQ(glenoid.voxmapResolution, 192);

  // 128 holds: the phantom CT's 0.5 mm pixels allow fewer cells still; the shell follows.
  write(row(128, 1, 0.8) + row(192, 2, 2.5));
  b = bm::BuildSession(glenoid, req);
  const bm::Scene& used = b.setup->GetScene();
  EXPECT_GE(b.setup->Bone().Spacing(), 0.5 - 1e-12);
  EXPECT_GT(used.voxmapResolution, 60);
  EXPECT_LT(used.voxmapResolution, 100);
  EXPECT_EQ(used.shellResolution, int(std::lround(340.0 * used.voxmapResolution / 192)));
  EXPECT_EQ(used.threads, 1);
  EXPECT_NE(b.gridReason.find("no finer than the CT's spacing"), std::string::npos) << b.gridReason;
  const int ctCells = used.voxmapResolution;

  // Only 64 holds: the measurement caps it below the CT's spacing.
  write(row(64, 2, 0.7) + row(128, 1, 1.3));
  b = bm::BuildSession(glenoid, req);
  EXPECT_EQ(b.setup->GetScene().voxmapResolution, 64);
  EXPECT_EQ(b.setup->GetScene().shellResolution, 113);
  EXPECT_EQ(b.setup->GetScene().threads, 2);
  EXPECT_EQ(b.gridReason.find("no finer than the CT's spacing"), std::string::npos) << b.gridReason;
  EXPECT_LT(64, ctCells);

  // A 1 mm burr on the same CT needs 0.25 mm voxels: the measured limit (128) wins over the CT.
  write(row(128, 1, 0.8));
  bm::Scene burr = glenoid;
  burr.tool = {{"type", "burr"}, {"radius_mm", 1.0}};
  b = bm::BuildSession(burr, req);
  EXPECT_EQ(b.setup->GetScene().voxmapResolution, 128);
  EXPECT_LT(b.setup->Bone().Spacing(), 0.5);
  ::unsetenv("BM_SESSION_BENCHMARK_CSV");
  std::filesystem::remove(table);
}

TEST(SessionBuilder, DurationsFramesAndTouchPlacementFollowTheDevice) {
  const bm::Scene scene = SmallDrilling();
  bm::SessionRequest r;
  r.mode = bm::ScriptMode::Force;
  EXPECT_EQ(bm::BuildSession(scene, r).options.maxFrames, 2000); // 2 s at 1 kHz
  r.durationS = 0.5;
  EXPECT_EQ(bm::BuildSession(scene, r).options.maxFrames, 500);
  r.rateHz = 500;
  EXPECT_EQ(bm::BuildSession(scene, r).options.maxFrames, 250);
  r.maxFrames = 7;
  const bm::BuiltSession seven = bm::BuildSession(scene, r);
  EXPECT_EQ(seven.options.maxFrames, 7);
  EXPECT_NEAR(seven.durationS, 7.0 / 500, 1e-12);

  bm::SessionRequest touch;
  touch.device = bm::SessionDevice::Touch;
  const bm::BuiltSession tb = bm::BuildSession(scene, touch);
  const bm::TrialSpec& t = tb.setup->GetScene().trial;
  EXPECT_TRUE(tb.options.deviceOffsetMm.isApprox(t.entry + t.axis.normalized() * 10.0, 1e-12));
  EXPECT_EQ(tb.options.maxFrames, -1); // a hand on the device: no limit
  EXPECT_LT(tb.durationS, 0);
  EXPECT_EQ(tb.options.overrunLimit, 5);
  EXPECT_DOUBLE_EQ(tb.options.proxy.coupling.forceScale, bm::SessionForceScale(*tb.setup));

  bm::SessionRequest mouse;
  mouse.device = bm::SessionDevice::Mouse;
  mouse.mouseDepthMm = -1.25;
  const bm::BuiltSession mb = bm::BuildSession(scene, mouse);
  ASSERT_TRUE(mb.mouse);
  EXPECT_EQ(mb.device, mb.mouse);
  const bm::DevicePose p = bm::ToolPoseAtDepth(*mb.setup, -1.25);
  EXPECT_NEAR(bm::ToolDepthMm(*mb.setup, p.positionMm, p.rotation), -1.25, 1e-12);
}

// The mouse proxy reams each wheel notch at the scene's feed: the thrust of a notch stays the
// steady cut's, where the stiff arm behind the mouse drove it at the force model's largest feed
// (1 mm/rev, 50 times the drill's 0.02) for the frames the notch took.
TEST(SessionBuilder, AMouseWheelNotchIsCutAtTheScenesFeedWithoutABurst) {
  const bm::Scene scene = SmallDrilling();
  auto run = [&](double maxFeed) {
    bm::SessionRequest mouse;
    mouse.device = bm::SessionDevice::Mouse;
    mouse.mouseDepthMm = 0.3; // the lips already in the block
    mouse.realTime = false;
    mouse.maxFrames = 3000;
    bm::BuiltSession b = bm::BuildSession(scene, mouse);
    if (maxFeed > 0)
      b.options.proxy.maxFeedMmPerRev = maxFeed;
    b.options.recordCapacity = 4000;
    bm::HapticSession session(*b.setup, b.device, b.options);
    session.Start();
    // A notch (0.1 mm deeper) every 500 frames, as a hand turns the wheel.
    for (int notch = 1; notch <= 4; ++notch) {
      while (session.Snapshot().frame < 500 * notch &&
             session.Snapshot().state == bm::SessionState::Running)
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      b.mouse->SetPose(bm::ToolPoseAtDepth(*b.setup, 0.3 + 0.1 * notch));
    }
    EXPECT_TRUE(session.WaitUntilPaused(600));
    session.Stop();
    std::vector<bm::FrameRecord> rec;
    session.DrainRecords(rec);
    double maxFeedSeen = 0, maxThrust = 0;
    for (const auto& f : rec) {
      maxFeedSeen = std::max(maxFeedSeen, f.feedMmPerRev);
      maxThrust = std::max(maxThrust, f.thrustN);
    }
    return std::make_pair(maxFeedSeen, maxThrust);
  };
  const double feed = scene.trial.feedMmPerRev;
  const auto [notchFeed, notchThrust] = run(0);
  EXPECT_LE(notchFeed, feed * (1 + 1e-12));
  EXPECT_GT(notchThrust, 0.0); // the notches cut
  // The force model at the scene's feed, fully engaged: no notch pushes harder.
  const bm::BuiltSession ref = bm::BuildSession(scene, bm::SessionRequest{});
  const bm::EdgeIntegral steady =
      bm::IntegrateEdges(ref.setup->Tool(), ref.setup->Model(), feed, scene.trial.speedRpm);
  EXPECT_LE(notchThrust, 1.05 * steady.thrustN);
  // At the force model's largest feed, as before, a notch pushed several times harder.
  const auto [burstFeed, burstThrust] = run(1.0);
  EXPECT_GT(burstFeed, 5 * feed);
  EXPECT_GT(burstThrust, 3 * notchThrust);
}

TEST(SessionBuilder, BadRequestsAreRefusedByNameBeforeTheBoneIsBuilt) {
  bm::Scene scene = SmallDrilling();
  auto refusal = [&](const bm::SessionRequest& r) {
    return Refusal([&] { bm::BuildSession(scene, r); });
  };
  bm::SessionRequest r;
  r.device = bm::SessionDevice::Robot;
  r.mode = bm::ScriptMode::Hand;
  EXPECT_NE(refusal(r).find("a robot session only feeds; mode 'hand'"), std::string::npos)
      << refusal(r);
  r = {};
  r.forceScale = 1e6;
  EXPECT_NE(refusal(r).find("force scale (tool N per device N) must be in [0.001, 1000]"),
            std::string::npos)
      << refusal(r);
  r = {};
  r.rateHz = 5;
  EXPECT_NE(refusal(r).find("haptic rate (Hz) must be in [10, 10000], not 5"), std::string::npos);
  r = {};
  r.mode = bm::ScriptMode::Trajectory;
  EXPECT_NE(refusal(r).find("needs trajectory samples"), std::string::npos);
  // A hand on the device at a rate where the sampled coupling is not passive (it pushed 190 mm
  // through the block at 10 Hz); a robot feeding at 10 Hz is a position source and runs.
  for (const bm::ScriptMode mode : {bm::ScriptMode::Force, bm::ScriptMode::Hand}) {
    r = {};
    r.mode = mode;
    r.rateHz = 10;
    EXPECT_NE(refusal(r).find("passive only above 50 Hz"), std::string::npos) << refusal(r);
    r.rateHz = 60;
    EXPECT_NO_THROW(bm::ValidateSessionRequest(r));
  }
  r = {};
  r.device = bm::SessionDevice::Touch;
  r.rateHz = 20;
  EXPECT_NE(refusal(r).find("too low for a hand on the device"), std::string::npos);
  r = {};
  r.device = bm::SessionDevice::Robot;
  r.rateHz = 10;
  EXPECT_NO_THROW(bm::ValidateSessionRequest(r));
  r = {};
  r.mode = bm::ScriptMode::Force;
  r.appliedForceN = 50;
  EXPECT_NE(refusal(r).find("applied force (N at the device) must be in [0, 3.3]"),
            std::string::npos)
      << refusal(r);
  r = {};
  r.durationS = -1;
  EXPECT_NE(refusal(r).find("session duration (s)"), std::string::npos);
  EXPECT_NE(Refusal([] {
              bm::SessionDeviceFromString("phantom");
            }).find("scripted, robot, touch or mouse, not 'phantom'"),
            std::string::npos);
  // A request refused before the bone: a CT scene whose CT does not exist still names the request.
  scene.bone.type = "ct";
  scene.bone.ct = {{"ct", "/nonexistent/ct.nrrd"}};
  r = {};
  r.rateHz = 1e6;
  EXPECT_NE(refusal(r).find("haptic rate"), std::string::npos);
}

TEST(SceneBone, BlockSceneIsTheSceneBlock) {
  const bm::Scene scene = SmallDrilling();
  const bm::Voxmap a = bm::MakeSceneBone(scene);
  const bm::Voxmap b = bm::MakeSceneBlock(scene);
  EXPECT_EQ(a.Dims(), b.Dims());
  EXPECT_DOUBLE_EQ(a.BoneVolume(), b.BoneVolume());
  EXPECT_GT(a.BoneVolume(), 0.0);
}

} // namespace

// The force scale a hand gets by default is the tool's: a firm 2.5 N push on the Touch balances
// the tool's fully engaged thrust at a surgeon's feed (the drill's 0.05 mm/rev, the reamer's
// 0.2 mm/s), so the drill is not pushed with the reamer's 125 N.
TEST(SessionBuilder, TheForceScaleIsTheTools) {
  const auto scaleOf = [](const std::string& name) {
    bm::SceneOverrides o;
    o.voxmapResolution = 32;
    bm::Scene scene = bm::ApplyOverrides(bm::ResolveScene(name), o);
    // The scale is the tool's and the speed's: a block stands in for a CT bone (also in builds
    // without CT import).
    scene.bone.type = "block";
    scene.bone.sizeMm = {40, 40, 5};
    scene.bone.ct = nullptr;
    bm::SessionRequest touch;
    touch.device = bm::SessionDevice::Touch;
    const bm::BuiltSession b = bm::BuildSession(scene, touch);
    const double s = b.options.proxy.coupling.forceScale;
    EXPECT_DOUBLE_EQ(s, bm::SessionForceScale(*b.setup)) << name;
    // The push at that scale balances the surgeon's feed's thrust, to one significant figure.
    bm::FeedBalance balance(b.setup->Tool(), b.setup->Model());
    const double n = scene.trial.speedRpm;
    const double exact =
        balance.FullThrust(bm::SurgeonFeedMmPerRev(b.setup->Tool(), n), n) / bm::kFirmPushN;
    const double unit = std::pow(10.0, std::floor(std::log10(exact)));
    EXPECT_NEAR(s, std::round(exact / unit) * unit, 1e-9 * s) << name << ": exact " << exact;
    // A robot and the mouse are position sources: unscaled; a given scale is kept.
    bm::SessionRequest mouse;
    mouse.device = bm::SessionDevice::Mouse;
    EXPECT_DOUBLE_EQ(bm::BuildSession(scene, mouse).options.proxy.coupling.forceScale, 1.0);
    touch.forceScale = 7.5;
    EXPECT_DOUBLE_EQ(bm::BuildSession(scene, touch).options.proxy.coupling.forceScale, 7.5);
    return s;
  };
  const double drill = scaleOf("drilling"), reamer = scaleOf("glenoid"), burr = scaleOf("skull");
  EXPECT_DOUBLE_EQ(reamer, 50.0); // the reamer's (Docs/Session.md, "Force scaling")
  EXPECT_LT(drill, reamer / 4);
  EXPECT_GT(burr, 0.1); // the small burr's thrust is under the push: the hand feels it magnified
  EXPECT_LT(burr, drill);
  std::cout << "[force scale] drill " << drill << ", glenoid reamer " << reamer << ", skull burr "
            << burr << "\n";
  // The surgeon's feeds: the drill's per revolution, the others' per second.
  const auto tool = [](const std::string& name) {
    return bm::MakeTool(bm::ResolveScene(name).tool);
  };
  EXPECT_DOUBLE_EQ(bm::SurgeonFeedMmPerRev(*tool("drilling"), 1000), 0.05);
  EXPECT_DOUBLE_EQ(bm::SurgeonFeedMmPerRev(*tool("glenoid"), 500), 0.2 * 60 / 500);
  EXPECT_THROW(bm::SurgeonFeedMmPerRev(*tool("glenoid"), 0), std::invalid_argument);
}

TEST(SessionBuilder, AToolNeverStartsInsideBone) {
  // The drilling scene's drill, tilted 45 deg from the block's normal with its tip 0.02 mm above
  // the entry (the scene's clearance): the low side of its tip cone reaches into the block. The
  // session starts it further out along the axis, says so, and its first frame has no contact:
  // the proxy is where the device is (the contact would have pushed it out sideways).
  bm::SceneOverrides o;
  o.voxmapResolution = 64;
  const bm::Scene upright = bm::ApplyOverrides(bm::ResolveScene("drilling"), o);
  o.entryMm = upright.trial.entry;
  o.axis = Eigen::Vector3d(std::sqrt(0.5), 0, std::sqrt(0.5));
  const bm::Scene tilted = bm::ApplyOverrides(upright, o);

  bm::SessionRequest r;
  r.realTime = false;
  r.maxFrames = 3;
  // The scene as it is: clear (the tool starts where the scene says, every checksum unchanged).
  const bm::BuiltSession clear = bm::BuildSession(upright, r);
  EXPECT_EQ(clear.startLiftMm, 0.0);
  EXPECT_EQ(clear.startNote, "");

  bm::BuiltSession b = bm::BuildSession(tilted, r);
  const double h = b.setup->Bone().Spacing();
  EXPECT_GT(b.startLiftMm, h);
  EXPECT_LT(b.startLiftMm, 1.5); // the cone's low side is under a millimetre deep
  EXPECT_NE(b.startNote.find("further out along its axis"), std::string::npos) << b.startNote;
  // The start is on the axis, that far out, and clear by the rule itself.
  const bm::DevicePose start = StartPose(b);
  EXPECT_NEAR(bm::ToolDepthMm(*b.setup, start.positionMm, start.rotation),
              -tilted.trial.clearanceMm - b.startLiftMm, 1e-9);
  EXPECT_EQ(bm::StartLiftMm(*b.setup, -tilted.trial.clearanceMm - b.startLiftMm, 0.0), 0.0);
  b.options.recordCapacity = 16;
  bm::HapticSession session(*b.setup, b.device, b.options);
  session.Start();
  EXPECT_TRUE(session.WaitUntilPaused(60));
  session.Stop();
  std::vector<bm::FrameRecord> rec;
  session.DrainRecords(rec);
  ASSERT_FALSE(rec.empty());
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(rec[0].proxyPos[a], rec[0].devicePos[a], 1e-9) << "axis " << a;

  // Without the rule (the scene's start), the same tool is in the block: the rule is what moved it.
  EXPECT_GT(bm::StartLiftMm(*b.setup, -tilted.trial.clearanceMm, h), h);
  // Bone it cannot leave within the allowed lift is refused, naming the reason.
  try {
    bm::StartLiftMm(*b.setup, -tilted.trial.clearanceMm, h, 0.01);
    ADD_FAILURE() << "a tool held in bone was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot start clear of the bone"), std::string::npos);
  }
}
