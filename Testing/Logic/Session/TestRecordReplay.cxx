// Recording a session to CSV and HDF5, reading it back, and replaying it to the same forces.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>

#include "bmHapticSession.h"
#include "bmReplay.h"
#include "bmScriptedDevice.h"
#include "bmSessionRecorder.h"
#include "bmSessionTestUtil.h"

namespace {

bm::Recording RunRecordedSession(const bm::Scene& scene, bool pauseMidway) {
  bm::MachiningSetup setup(scene, bm::MakeSceneBlock(scene));
  bm::ScriptedDeviceOptions so;
  so.mode = bm::ScriptMode::Force; // the hand reacts to the forces: a closed loop to replay
  so.startMm = {0, 0, 0.02};
  so.appliedForceN = 1.5;
  so.rotation = setup.ToolRotation();
  auto dev = std::make_shared<bm::ScriptedDevice>(so);
  bm::SessionOptions o;
  o.realTime = false;
  o.overrunLimit = -1;
  o.maxFrames = 300;
  bm::HapticSession session(setup, dev, o);
  session.Start();
  if (pauseMidway) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    session.Pause();
    session.WaitUntilPaused(30);
    session.Resume();
  }
  while (!session.WaitUntilPaused(30) ||
         session.Snapshot().pauseReason != bm::PauseReason::Finished) {
    if (session.Snapshot().pauseReason == bm::PauseReason::User)
      session.Resume();
  }
  session.Stop();
  bm::Recording rec;
  session.DrainRecords(rec.frames);
  rec.meta = {{"scene", scene.ToJson()}, {"session", bm::SessionOptionsToJson(o, dev->Limits())}};
  return rec;
}

TEST(RecordReplay, CsvAndHdf5RoundTripAndReplayReproducesTheForces) {
  const bm::Scene scene = bm::test::DrillScene({3, 3, 1.0}, 64, 192);
  const bm::Recording rec = RunRecordedSession(scene, true);
  ASSERT_EQ(rec.frames.size(), 300u);
  const auto dir = std::filesystem::temp_directory_path() / "bm_record_test";
  std::filesystem::create_directories(dir);
  const std::string csv = (dir / "s.csv").string(), h5 = (dir / "s.h5").string();
  bm::WriteRecording(csv, rec);
  const bm::Recording a = bm::ReadRecording(csv);
  ASSERT_EQ(a.frames.size(), rec.frames.size());
  EXPECT_EQ(a.meta, rec.meta);
  for (size_t i = 0; i < a.frames.size(); ++i)
    ASSERT_EQ(a.frames[i].ToRow(), rec.frames[i].ToRow()) << i;
  if (bm::HasHdf5()) {
    bm::WriteRecording(h5, rec);
    const bm::Recording b = bm::ReadRecording(h5);
    ASSERT_EQ(b.frames.size(), rec.frames.size());
    EXPECT_EQ(b.meta, rec.meta);
    for (size_t i = 0; i < b.frames.size(); ++i)
      ASSERT_EQ(b.frames[i].ToRow(), rec.frames[i].ToRow()) << i;
  } else {
    EXPECT_THROW(bm::WriteRecording(h5, rec), std::runtime_error);
  }
  // Replay from the file: a fresh bone, the recorded poses, the same forces to the bit.
  bm::MachiningSetup fresh(bm::RecordedScene(a), bm::MakeSceneBlock(bm::RecordedScene(a)));
  const bm::ReplayResult r = bm::Replay(a, fresh);
  std::cout << "[replay] " << r.frames << " frames: max |dF| " << r.maxCouplingForceDiffN
            << " N, thrust " << r.maxThrustDiffN << " N, torque " << r.maxTorqueDiffNmm
            << " N mm, proxy " << r.maxProxyDiffMm << " mm\n";
  EXPECT_EQ(r.frames, 300);
  EXPECT_EQ(r.maxCouplingForceDiffN, 0.0);
  EXPECT_EQ(r.maxDeviceForceDiffN, 0.0);
  EXPECT_EQ(r.maxThrustDiffN, 0.0);
  EXPECT_EQ(r.maxTorqueDiffNmm, 0.0);
  double maxThrust = 0;
  for (const auto& f : rec.frames)
    maxThrust = std::max(maxThrust, f.thrustN);
  EXPECT_GT(maxThrust, 0.5); // it did drill
  EXPECT_EQ(r.maxProxyDiffMm, 0.0);
  EXPECT_EQ(r.maxFeedDiffMmPerRev, 0.0);
  EXPECT_EQ(r.maxRemovedVolumeDiffMm3, 0.0);
  EXPECT_EQ(r.maxRemovedVoxelsDiff, 0);
  EXPECT_TRUE(r.Differing(1e-9).empty());
  // A tampered recording does not reproduce.
  bm::Recording t = a;
  t.frames[150].devicePos[2] -= 0.05;
  bm::MachiningSetup fresh2(bm::RecordedScene(a), bm::MakeSceneBlock(bm::RecordedScene(a)));
  EXPECT_GT(bm::Replay(t, fresh2).maxCouplingForceDiffN, 1e-3);
  // Every quantity a frame produces is compared: an edit of any one of them is found, named.
  struct Edit {
    const char* quantity;
    std::function<void(bm::FrameRecord&)> change;
  };
  const std::vector<Edit> edits = {
      {"device force", [](bm::FrameRecord& f) { f.deviceForce[2] *= 2; }},
      {"device force",
       [](bm::FrameRecord& f) {
         f.deviceForce = {0, 0, 0};
       }},
      {"proxy position", [](bm::FrameRecord& f) { f.proxyPos[0] += 5; }},
      {"removed volume",
       [](bm::FrameRecord& f) { f.removedVolumeMm3 = 10 * f.removedVolumeMm3 + 1e-3; }},
      {"removed voxels", [](bm::FrameRecord& f) { f.removedVoxels += 7; }},
      {"feed", [](bm::FrameRecord& f) { f.feedMmPerRev += 0.01; }},
      {"thrust", [](bm::FrameRecord& f) { f.thrustN += 0.5; }},
      {"torque", [](bm::FrameRecord& f) { f.torqueNmm += 0.5; }}};
  for (const Edit& e : edits) {
    bm::Recording edited = a;
    for (size_t i = 100; i < 200; ++i)
      e.change(edited.frames[i]);
    bm::MachiningSetup again(bm::RecordedScene(a), bm::MakeSceneBlock(bm::RecordedScene(a)));
    const std::vector<std::string> differing = bm::Replay(edited, again).Differing(1e-9);
    EXPECT_NE(std::find(differing.begin(), differing.end(), e.quantity), differing.end())
        << e.quantity << " edited, not found";
  }
  // The frame and time columns: the session's frames in order, at frame / rate.
  bm::Recording renumbered = a;
  renumbered.frames[10].frame = 11;
  EXPECT_THROW(bm::CheckReplayable(renumbered), std::runtime_error);
  bm::Recording gap = a;
  gap.frames.erase(gap.frames.begin() + 20);
  EXPECT_THROW(bm::CheckReplayable(gap), std::runtime_error);
  bm::Recording retimed = a;
  retimed.frames[30].timeS += 0.5;
  try {
    bm::CheckReplayable(retimed);
    ADD_FAILURE() << "an edited time was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 30 of the recording is at time"), std::string::npos)
        << e.what();
  }
  // Bad files are refused.
  EXPECT_THROW(bm::ReadRecording((dir / "missing.csv").string()), std::runtime_error);
  std::filesystem::remove_all(dir);
}

} // namespace
