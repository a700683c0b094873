// bmProgrammableDevice.h - a device whose pose another thread sets: the GUI's mouse or keyboard
// driven proxy. SetPose() may be called from any thread at any rate; the haptic thread
// reads it without waiting (DeviceStateBuffer). The force the session sends can be read back for
// display (LastForce()). Always built.
//
// Slew limit: with SetMaxSpeed(v) the pose the session reads moves toward the last one set at no
// more than v mm/s of session time (Advance's dt), so a step of the GUI's depth (a mouse-wheel
// click of 0.1 mm) is spread over frames instead of arriving in one. The first pose is taken as
// it is; rotation and buttons follow at once.
#pragma once

#include <atomic>

#include "bmDevice.h"

namespace bm {

class ProgrammableDevice final : public Device {
public:
  /// limits: what the session may send (defaults: the Touch's, so a mouse session feels like one).
  explicit ProgrammableDevice(const DeviceLimits& limits = {}) : Limits_(limits) {}
  std::string Name() const override { return "programmable"; }
  DeviceLimits Limits() const override { return Limits_; }
  /// Any thread: the new pose (mm, device frame).
  void SetPose(const DevicePose& pose) { State_.PutPose(pose); }
  /// Any thread: the last force the session sent, N.
  Eigen::Vector3d LastForce() const { return State_.GetForce(); }
  /// Any thread: the slew limit, mm/s (device frame); <= 0 = none (default).
  void SetMaxSpeed(double mmPerS) { MaxSpeed_.store(mmPerS); }
  double MaxSpeed() const { return MaxSpeed_.load(); }
  void Advance(double timeS, double dtS) override;
  DeviceStatus Read(DevicePose& pose) override;
  DeviceStatus Write(const Eigen::Vector3d& forceN) override;

private:
  DeviceLimits Limits_;
  DeviceStateBuffer State_;
  DevicePose Last_, Target_;
  std::atomic<double> MaxSpeed_{0};
  double Dt_ = 0;     // s, the last frame's length
  bool Have_ = false; // a pose has been read
};

} // namespace bm
