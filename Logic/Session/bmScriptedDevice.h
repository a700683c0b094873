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
//  - Hand: the Force mode's mass and damping pushed the way a hand pushes: the push along -axis
//    rises smoothly (half cosine over handRampS) to appliedForceN, then wavers slowly (+-10 % at
//    0.3-0.7 Hz), and a physiological tremor of handTremorN (three sines each across two lateral
//    directions, 8-12 Hz) acts across the axis. Frequencies and phases come from handSeed
//    (std::mt19937_64), so a seed gives the same run every time; the total push never exceeds
//    the device's maximum force.
// Force and Hand modes take an applied force in [0, limits.maxForceN] (the device's range).
// A trained hand (stopAtBreakthrough) stops pushing at breakthrough, as surgeons are trained to:
// once the force the device renders along the axis, having held at least half the push, falls
// below half of its peak so far (the far cortex giving way), the hand reacts after reactionS: its
// push falls to zero over 50 ms and it holds (its damping rises to holdDampingNsPerMm). Without
// it the hand keeps pushing through, and the session's runaway rule stops it.
// Faults can be scripted for safety tests and fault drills: from `errorAtS` on Read reports an
// error, from `silentAtS` on the device stops answering.
//
// Units: mm, s, N, kg, rpm, mm/rev.
#pragma once

#include <cstdint>
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
/// increasing. Throws std::runtime_error naming the file and line on bad input: not a regular
/// file, fewer than 2 samples, a value not finite, a time outside [0, 3600] s, a position beyond
/// +-10000 mm, a zero quaternion.
std::vector<TrajectorySample> LoadTrajectoryCsv(const std::string& path);

enum class ScriptMode { Feed, Force, Trajectory, Hand };
const char* ToString(ScriptMode m);

struct ScriptedDeviceOptions {
  ScriptMode mode = ScriptMode::Feed;
  Eigen::Vector3d startMm = Eigen::Vector3d::Zero(); ///< stylus position at t = 0, mm
  Eigen::Vector3d axis{0, 0, 1}; ///< unit vector out of the bone; motion is along -axis
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity(); ///< stylus orientation (Feed, Force)
  double feedMmPerRev = 0.02;                             ///< Feed: f, mm/rev
  double speedRpm = 1000;                                 ///< Feed: n, rpm
  double appliedForceN = 2.0;    ///< Force: push along -axis; Hand: the firm push it rises to, N
  double handRampS = 0.5;        ///< Hand: rise time of the push, s
  double handTremorN = 0.1;      ///< Hand: lateral tremor amplitude (each direction), N
  uint64_t handSeed = 1;         ///< Hand: seed of the tremor's and waver's frequencies and phases
  double massKg = 0.1;           ///< Force: moving mass, kg
  double dampingNsPerMm = 0.005; ///< Force: c, N s/mm (5 N s/m)
  bool stopAtBreakthrough = false;  ///< Force, Hand: a trained hand's stop (above; default off)
  double reactionS = 0.1;           ///< its reaction time, s (default 0.1, a trained hand's)
  double holdDampingNsPerMm = 0.05; ///< its damping once it holds, N s/mm (default 50 N s/m)
  std::vector<TrajectorySample> trajectory; ///< Trajectory: samples, times increasing
  DeviceLimits limits;                      ///< nominal limits (default: the Touch)
  double errorAtS = -1;                     ///< >= 0: Read reports an error from then on
  double silentAtS = -1;                    ///< >= 0: the device stops answering from then on
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
  /// The pose at time t (s) for Feed and Trajectory modes (Force and Hand modes: the current pose).
  DevicePose PoseAt(double timeS) const;
  /// Hand mode: the hand's applied force at time t (s), device frame, N (Force mode: the constant
  /// push; other modes: zero).
  Eigen::Vector3d HandForce(double timeS) const;
  /// A trained hand: when it felt the breakthrough (s; < 0: not yet).
  double BreakthroughFeltAtS() const { return FeltAt_; }

private:
  ScriptedDeviceOptions O_;
  DevicePose Pose_;
  double Time_ = 0;
  Eigen::Vector3d Velocity_ = Eigen::Vector3d::Zero(); // Force mode, mm/s
  Eigen::Vector3d Force_ = Eigen::Vector3d::Zero();    // last written, N
  double PeakResist_ = 0; // trained hand: the largest force rendered back along the axis, N
  double FeltAt_ = -1;    // trained hand: when the resistance gave way, s
  std::string Error_;
  struct Sine {
    double amplitude, hz, phase; // N (or fraction), Hz, rad
  };
  std::vector<Sine> Waver_, TremorU_, TremorV_; // Hand mode, drawn from handSeed
  /// The trained hand's push factor at time t (s): 1 until it reacts, then down to 0.
  double Release(double timeS) const;
  Eigen::Vector3d U_ = Eigen::Vector3d::UnitX(), V_ = Eigen::Vector3d::UnitY(); // across axis
};

} // namespace bm
