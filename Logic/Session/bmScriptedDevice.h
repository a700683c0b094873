// bmScriptedDevice.h - a device driven by a script instead of a hand: robot-driven trials and
// recorded trajectories. Always built; it drives the tests and `bmsim run --device scripted`.
//
// Modes:
//  - Feed: the stylus moves along -axis at v = f n / 60 mm/s from `start` (a robot prescribing
//    feed and speed, the way the papers validate).
//  - Force: a robot (or hand) of mass m and damping c pushes along -axis with a constant applied
//    force; the force the session writes acts on it too (m a = F_applied + F_device - c v), so it
//    settles where the rendered force balances the applied one.
//  - Trajectory: poses interpolated (linearly; rotation by slerp) from timed samples, e.g. read
//    from a file (LoadTrajectoryCsv) or a recorded session (bmReplay.h).
// Faults can be scripted for safety tests and fault drills: from `errorAtS` on Read reports an
// error, from `silentAtS` on the device stops answering.
//
// Units: mm, s, N, kg, rpm, mm/rev.
#pragma once

#include <string>
#include <vector>

#include "bmDevice.h"

namespace bm {

struct TrajectorySample {
  double timeS = 0;
  Eigen::Vector3d positionMm = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  uint32_t buttons = 0;
};

/// Reads "time_s,x_mm,y_mm,z_mm[,qw,qx,qy,qz]" rows (header line and '#' lines skipped), times
/// increasing. Throws std::runtime_error naming the file and line on bad input.
std::vector<TrajectorySample> LoadTrajectoryCsv(const std::string& path);

enum class ScriptMode { Feed, Force, Trajectory };
const char* ToString(ScriptMode m);

struct ScriptedDeviceOptions {
  ScriptMode mode = ScriptMode::Feed;
  Eigen::Vector3d startMm = Eigen::Vector3d::Zero(); ///< stylus position at t = 0, mm
  Eigen::Vector3d axis{0, 0, 1}; ///< unit vector out of the bone; motion is along -axis
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity(); ///< stylus orientation (Feed, Force)
  double feedMmPerRev = 0.02;                             ///< Feed: f, mm/rev
  double speedRpm = 1000;                                 ///< Feed: n, rpm
  double appliedForceN = 2.0;                             ///< Force: push along -axis, N
  double massKg = 0.1;                                    ///< Force: moving mass, kg
  double dampingNsPerMm = 0.005;                          ///< Force: c, N s/mm (5 N s/m)
  std::vector<TrajectorySample> trajectory;               ///< Trajectory: samples, times increasing
  DeviceLimits limits;                                    ///< nominal limits (default: the Touch)
  double errorAtS = -1;  ///< >= 0: Read reports an error from then on
  double silentAtS = -1; ///< >= 0: the device stops answering from then on
};

class ScriptedDevice final : public Device {
public:
  /// Throws std::invalid_argument on an empty or unordered trajectory, or a non-positive mass.
  explicit ScriptedDevice(const ScriptedDeviceOptions& o);
  std::string Name() const override { return "scripted"; }
  DeviceLimits Limits() const override { return O_.limits; }
  void Advance(double timeS, double dtS) override;
  DeviceStatus Read(DevicePose& pose) override;
  DeviceStatus Write(const Eigen::Vector3d& forceN) override;
  std::string LastError() const override { return Error_; }
  const ScriptedDeviceOptions& Options() const { return O_; }
  /// The pose at time t (s) for Feed and Trajectory modes (Force mode: the current pose).
  DevicePose PoseAt(double timeS) const;

private:
  ScriptedDeviceOptions O_;
  DevicePose Pose_;
  double Time_ = 0;
  Eigen::Vector3d Velocity_ = Eigen::Vector3d::Zero(); // Force mode, mm/s
  Eigen::Vector3d Force_ = Eigen::Vector3d::Zero();    // last written, N
  std::string Error_;
};

} // namespace bm
