// bmProgrammableDevice.h - a device whose pose another thread sets: the GUI's mouse or keyboard
// driven proxy. SetPose() may be called from any thread at any rate; the haptic thread
// reads it without waiting (DeviceStateBuffer). The force the session sends can be read back for
// display (LastForce()). Always built.
#pragma once

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
  DeviceStatus Read(DevicePose& pose) override;
  DeviceStatus Write(const Eigen::Vector3d& forceN) override;

private:
  DeviceLimits Limits_;
  DeviceStateBuffer State_;
  DevicePose Last_;
};

} // namespace bm
