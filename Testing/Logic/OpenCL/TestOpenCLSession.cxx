// A haptic session on the OpenCL backend is the CPU backend's session, frame for frame: the
// scripted hand reams the analytic glenoid (bmTestGlenoid.h) through the proxy, whose contact and
// surface shell read the host's voxmap, which the OpenCL engine keeps current after every frame
// (bmOpenCLEngine.h). Every recorded quantity of every frame, and the cut bone, must be identical
// on whatever OpenCL device runs the test (PoCL in CI; BM_TEST_OPENCL_DEVICE names another).
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bmHapticSession.h"
#include "bmOpenCLBackend.h"
#include "bmOpenCLDevice.h"
#include "bmScriptedDevice.h"
#include "../Session/bmTestGlenoid.h"
#include "../Session/bmTestGlenoidHand.h"

namespace {

struct SessionRun {
  std::vector<bm::FrameRecord> records;
  bm::Voxmap bone;
  std::string engine;
};

SessionRun HandSession(const std::string& backend, int frames) {
  nlohmann::json j = bmtest::AnalyticGlenoidScene(64, 113).ToJson();
  j["backend"] = backend;
  const bm::Scene scene = bm::Scene::FromJson(j);
  const char* device = std::getenv("BM_TEST_OPENCL_DEVICE");
  bm::MachiningSetup setup(scene, bmtest::AnalyticGlenoidVoxmap(bmtest::AnalyticGlenoidSpacing(64)),
                           device ? device : "");
  SessionRun r;
  {
    bm::HapticSession session(setup,
                              std::make_shared<bm::ScriptedDevice>(bmtest::GlenoidHand(setup)),
                              bmtest::GlenoidHandSession(frames));
    session.Start();
    EXPECT_TRUE(session.WaitUntilPaused(600));
    session.Stop();
    session.DrainRecords(r.records);
  }
  r.engine = setup.GetEngine().Name();
  setup.GetEngine().SyncBone();
  r.bone = setup.Bone();
  return r;
}

TEST(OpenCLSession, TheGlenoidHandSessionIsTheCpuBackendsFrameForFrame) {
  if (bm::ListOpenCLDevices().empty())
    GTEST_SKIP() << "no OpenCL device";
  bm::RegisterOpenCLBackend();
  const int frames = 1200;
  const SessionRun cpu = HandSession("cpu", frames);
  const SessionRun ocl = HandSession("opencl", frames);
  ASSERT_EQ(ocl.engine, "opencl/lazar"); // not a fallback to the CPU backend
  ASSERT_EQ(cpu.records.size(), size_t(frames));
  ASSERT_EQ(ocl.records.size(), cpu.records.size());
  double removed = 0;
  for (size_t k = 0; k < cpu.records.size(); ++k) {
    const bm::FrameRecord &a = cpu.records[k], &b = ocl.records[k];
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_EQ(a.proxyPos, b.proxyPos);
    EXPECT_EQ(a.devicePos, b.devicePos);
    EXPECT_EQ(a.couplingForce, b.couplingForce);
    EXPECT_EQ(a.deviceForce, b.deviceForce);
    EXPECT_EQ(a.thrustN, b.thrustN);
    EXPECT_EQ(a.torqueNmm, b.torqueNmm);
    EXPECT_EQ(a.feedMmPerRev, b.feedMmPerRev);
    EXPECT_EQ(a.removedVoxels, b.removedVoxels);
    EXPECT_EQ(a.removedVolumeMm3, b.removedVolumeMm3);
    removed += a.removedVolumeMm3;
    if (::testing::Test::HasFailure())
      return;
  }
  EXPECT_GT(removed, 10.0); // the comparison covered reaming, not a hand in the air (mm^3)
  EXPECT_TRUE(cpu.bone == ocl.bone);
}

} // namespace
