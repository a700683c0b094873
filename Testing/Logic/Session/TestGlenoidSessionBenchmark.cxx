// A benchmark, not a test of speed: the haptic session's frame time on a glenoid-sized reaming
// scene (the glenoid scene's 36.5 mm reamer at shell 340 over an analytic glenoid at the scene's
// voxmap spacing, 41.25 mm / 192), printed as p50/p99. It runs only when BM_SESSION_BENCH_FRAMES
// is set (the number of frames, e.g. 3000: the scripted robot's approach from 1.5 mm above the face
// and about 1 mm of reaming); otherwise it is skipped, so the unit-test runs stay short.
// BM_SESSION_BENCH_CANDIDATE_RADIUS sets ProxyOptions::candidateRadiusVoxels (0: every contact
// query scans the shell, as before the candidates). It asserts only what the run must do (cut bone,
// finite forces), never a time. It also prints a checksum of the proxy's path and forces, so that a
// change meant to be exact can be compared run to run.
//
//   BM_SESSION_BENCH_FRAMES=3000 build-session/Testing/Logic/BMSessionTests
//       --gtest_filter='SessionBenchmark.*'
//
// Figures (2 shared cores, 3000 frames, 2636 touching bone) and what the frame spends its time on:
// Docs/RealTime.md. Scanning every query (radius 0) and the candidates (radius 2, the default)
// give identical checksums.
//
// The bone: bmTestGlenoid.h's analytic glenoid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bmHapticSession.h"
#include "bmScriptedDevice.h"
#include "bmTestGlenoid.h"

namespace {

TEST(SessionBenchmark, GlenoidReamerFrameTime) {
  const char* env = std::getenv("BM_SESSION_BENCH_FRAMES");
  if (!env || std::atoi(env) <= 0)
    GTEST_SKIP() << "set BM_SESSION_BENCH_FRAMES=N to run N frames of the glenoid reamer session";
  const int frames = std::atoi(env);
  const bm::Scene scene = bmtest::AnalyticGlenoidScene(192, 340);
  bm::MachiningSetup setup(scene,
                           bmtest::AnalyticGlenoidVoxmap(bmtest::AnalyticGlenoidSpacing(192)));

  bm::ScriptedDeviceOptions d;
  d.mode = bm::ScriptMode::Feed;
  d.startMm = {0, 0, 1.5}; // the scene's clearance above the face centre
  d.feedMmPerRev = 0.1;
  d.speedRpm = 500;
  auto dev = std::make_shared<bm::ScriptedDevice>(d);
  bm::SessionOptions o;
  o.realTime = false;
  o.overrunLimit = -1;
  o.maxFrames = frames;
  o.speedRpm = 500;
  if (const char* r = std::getenv("BM_SESSION_BENCH_CANDIDATE_RADIUS")) // voxels; 0: scan always
    o.proxy.candidateRadiusVoxels = std::atof(r);
  bm::HapticSession session(setup, dev, o);
  session.Start();
  ASSERT_TRUE(session.WaitUntilPaused(3600));
  session.Stop();
  std::vector<bm::FrameRecord> rec;
  session.DrainRecords(rec);
  ASSERT_EQ(int64_t(rec.size()), frames);

  // Frame times (nearest-rank percentiles of the recorded compute times, not capped like the
  // session's histogram) over the whole run and over the frames that touch bone.
  std::vector<double> all, engaged;
  double removed = 0, thrust = 0, pathSum = 0, forceSum = 0;
  for (const bm::FrameRecord& r : rec) {
    all.push_back(r.frameMs);
    if (r.thrustN != 0 || r.removedVoxels > 0 || r.deviceForce[2] != 0)
      engaged.push_back(r.frameMs);
    removed += r.removedVolumeMm3;
    thrust += r.thrustN;
    pathSum += r.proxyPos[0] + r.proxyPos[1] + r.proxyPos[2];
    forceSum += r.deviceForce[0] + r.deviceForce[1] + r.deviceForce[2];
    ASSERT_TRUE(std::isfinite(r.deviceForce[0]) && std::isfinite(r.deviceForce[1]) &&
                std::isfinite(r.deviceForce[2]));
  }
  auto figures = [](std::vector<double> v) {
    std::ostringstream s;
    s.precision(4);
    if (v.empty())
      return std::string("none");
    std::sort(v.begin(), v.end());
    auto rank = [&](double q) { return v[std::min(v.size() - 1, size_t(q * double(v.size())))]; };
    const auto over = std::count_if(v.begin(), v.end(), [](double ms) { return ms > 1.0; });
    s << v.size() << " frames: p50 " << rank(0.5) << " ms, p99 " << rank(0.99) << " ms, max "
      << v.back() << " ms, over 1 ms " << over;
    return s.str();
  };
  const bm::FrameRecord& last = rec.back();
  std::cout << "[glenoid session] candidate radius " << o.proxy.candidateRadiusVoxels
            << " voxels\n[glenoid session] all " << figures(all)
            << "\n[glenoid session] in contact " << figures(engaged) << "\n";
  std::cout.precision(12);
  std::cout << "[glenoid session] checksum: removed " << removed << " mm^3, sum thrust " << thrust
            << " N, sum proxy " << pathSum << " mm, sum device force " << forceSum
            << " N, last proxy z " << last.proxyPos[2] << " mm, last thrust " << last.thrustN
            << " N\n";
  EXPECT_GT(removed, 0.0);
}

} // namespace
