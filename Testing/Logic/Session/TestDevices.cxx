// Devices, coupling, timing and the record ring: the pieces the session is built from.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

#include "bmFrameRecord.h"
#include "bmProgrammableDevice.h"
#include "bmScriptedDevice.h"
#include "bmTimingStats.h"
#include "bmVirtualCoupling.h"

namespace {

TEST(ScriptedDevice, FeedModeMovesAlongMinusAxisAtFeedTimesSpeed) {
  bm::ScriptedDeviceOptions o;
  o.startMm = {1, 2, 3};
  o.feedMmPerRev = 0.02;
  o.speedRpm = 1200; // 0.4 mm/s
  bm::ScriptedDevice d(o);
  d.Advance(0.5, 0.001);
  bm::DevicePose p;
  ASSERT_EQ(d.Read(p), bm::DeviceStatus::Ok);
  EXPECT_NEAR(p.positionMm(2), 3 - 0.2, 1e-12);
  EXPECT_NEAR(p.positionMm(0), 1, 1e-12);
}

TEST(ScriptedDevice, ForceModeSettlesWhereTheRenderedForceBalancesTheAppliedOne) {
  bm::ScriptedDeviceOptions o;
  o.mode = bm::ScriptMode::Force;
  o.appliedForceN = 1.5;
  bm::ScriptedDevice d(o);
  // A wall at z = -1 mm rendered as a stiff spring: the device must come to rest on it with the
  // spring carrying 1.5 N.
  bm::DevicePose p;
  for (int k = 0; k < 4000; ++k) {
    d.Advance(k * 0.001, 0.001);
    ASSERT_EQ(d.Read(p), bm::DeviceStatus::Ok);
    const double pen = std::max(0.0, -1.0 - p.positionMm(2));
    d.Write({0, 0, 2.0 * pen});
  }
  EXPECT_NEAR(2.0 * std::max(0.0, -1.0 - p.positionMm(2)), 1.5, 0.01);
}

TEST(ScriptedDevice, TrajectoryInterpolatesAndScriptedFaultsAreReported) {
  bm::ScriptedDeviceOptions o;
  o.mode = bm::ScriptMode::Trajectory;
  o.trajectory = {{0.0, {0, 0, 0}, Eigen::Matrix3d::Identity(), 0},
                  {1.0, {0, 0, -2}, Eigen::Matrix3d::Identity(), 1}};
  o.errorAtS = 0.8;
  bm::ScriptedDevice d(o);
  bm::DevicePose p;
  d.Advance(0.25, 0.001);
  ASSERT_EQ(d.Read(p), bm::DeviceStatus::Ok);
  EXPECT_NEAR(p.positionMm(2), -0.5, 1e-12);
  d.Advance(0.9, 0.001);
  EXPECT_EQ(d.Read(p), bm::DeviceStatus::Error);
  EXPECT_FALSE(d.LastError().empty());
  o.errorAtS = -1;
  o.silentAtS = 0.5;
  bm::ScriptedDevice s(o);
  s.Advance(0.6, 0.001);
  EXPECT_EQ(s.Read(p), bm::DeviceStatus::NoResponse);
  o.trajectory.clear();
  EXPECT_THROW(bm::ScriptedDevice bad(o), std::invalid_argument);
}

TEST(ScriptedDevice, LoadsTrajectoryFilesAndRefusesBadOnes) {
  const auto dir = std::filesystem::temp_directory_path() / "bm_traj_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir / "t.csv");
    f << "time_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n0,0,0,1,1,0,0,0\n0.5,0,0,0,1,0,0,0\n";
  }
  const auto t = bm::LoadTrajectoryCsv((dir / "t.csv").string());
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t[1].positionMm(2), 0.0);
  {
    std::ofstream f(dir / "bad.csv");
    f << "0,0,0,1\n0,0,0,2\n";
  }
  EXPECT_THROW(bm::LoadTrajectoryCsv((dir / "bad.csv").string()), std::runtime_error);
  EXPECT_THROW(bm::LoadTrajectoryCsv((dir / "missing.csv").string()), std::runtime_error);
  std::filesystem::remove_all(dir);
}

TEST(ProgrammableDevice, AnotherThreadSetsThePoseWhileTheHapticSideReads) {
  bm::ProgrammableDevice d;
  std::atomic<bool> stop{false};
  std::thread gui([&] {
    for (int i = 0; !stop.load(); ++i) {
      bm::DevicePose p;
      p.positionMm = {double(i % 100), 0, 0};
      d.SetPose(p);
    }
  });
  bm::DevicePose p;
  for (int k = 0; k < 2000; ++k) {
    ASSERT_EQ(d.Read(p), bm::DeviceStatus::Ok);
    ASSERT_EQ(d.Write({0, 0, 0.001 * k}), bm::DeviceStatus::Ok);
    ASSERT_GE(p.positionMm(0), 0.0);
    ASSERT_LT(p.positionMm(0), 100.0);
  }
  stop = true;
  gui.join();
  EXPECT_GE(d.LastForce()(2), 0.0);
}

TEST(VirtualCoupling, StiffnessAtOrBelowTheDevicesAndForcesClampedAndFinite) {
  bm::DeviceLimits touch; // 3.3 N, 0.4 N/mm
  bm::CouplingOptions o;
  o.stiffnessNPerMm = 5.0;
  bm::VirtualCoupling c(o, touch, 0.001);
  EXPECT_DOUBLE_EQ(c.Stiffness(), 0.4);
  EXPECT_NEAR(c.Damping(), 0.4 * 0.001, 1e-15); // B = K T by default
  const Eigen::Vector3d big = c.DeviceForce(c.Force({100, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}));
  EXPECT_LE(big.norm(), 3.3);
  EXPECT_NEAR(big.norm(), 3.3, 1e-9);
  const double nan = std::numeric_limits<double>::quiet_NaN(),
               inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(bm::VirtualCoupling::Clamp({nan, 0, 0}, 3.3), Eigen::Vector3d::Zero());
  EXPECT_EQ(bm::VirtualCoupling::Clamp({0, inf, 0}, 3.3), Eigen::Vector3d::Zero());
  EXPECT_EQ(c.DeviceForce(c.Force({nan, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0})),
            Eigen::Vector3d::Zero());
}

TEST(TimingHistogram, PercentilesMaximumAndOverruns) {
  bm::TimingHistogram h;
  for (int i = 1; i <= 100; ++i)
    h.Add(i * 0.01, i > 98); // 0.01 .. 1.00 ms
  const bm::TimingStats s = h.Stats();
  EXPECT_EQ(s.frames, 100);
  EXPECT_EQ(s.overruns, 2);
  EXPECT_NEAR(s.p50Ms, 0.50, 0.0011);
  EXPECT_NEAR(s.p99Ms, 0.99, 0.0011);
  EXPECT_DOUBLE_EQ(s.maxMs, 1.0);
}

TEST(RecordRing, CarriesRecordsAcrossThreadsAndCountsDrops) {
  bm::RecordRing ring(1024);
  std::vector<bm::FrameRecord> got;
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (int i = 0; i < 20000; ++i) {
      bm::FrameRecord r;
      r.frame = i;
      while (!ring.Push(r))
        std::this_thread::yield();
    }
    done = true;
  });
  while (!done.load() || ring.Drain(got) > 0)
    ring.Drain(got);
  producer.join();
  ring.Drain(got);
  ASSERT_EQ(got.size(), 20000u);
  for (size_t i = 0; i < got.size(); ++i)
    ASSERT_EQ(got[i].frame, int64_t(i));
  bm::RecordRing small(2);
  bm::FrameRecord r;
  EXPECT_TRUE(small.Push(r));
  EXPECT_TRUE(small.Push(r));
  EXPECT_FALSE(small.Push(r));
  EXPECT_EQ(small.Dropped(), 1u);
  // Row round trip.
  r.thrustN = 1.25;
  r.deviceQuat = {0.5, 0.5, 0.5, 0.5};
  r.flags = bm::FrameRecord::kResumed;
  const bm::FrameRecord back = bm::FrameRecord::FromRow(r.ToRow());
  EXPECT_EQ(back.thrustN, 1.25);
  EXPECT_EQ(back.deviceQuat, r.deviceQuat);
  EXPECT_EQ(back.flags, r.flags);
}

} // namespace
