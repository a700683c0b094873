#include "bmProgrammableDevice.h"

namespace bm {

DeviceStatus ProgrammableDevice::Read(DevicePose& pose) {
  uint64_t sample = 0;
  State_.TryGetPose(Last_, sample); // busy: keep the previous pose (the GUI is writing a new one)
  pose = Last_;
  return DeviceStatus::Ok;
}

DeviceStatus ProgrammableDevice::Write(const Eigen::Vector3d& forceN) {
  State_.TryPutForce(forceN); // display only: a busy buffer just shows last frame's force
  return DeviceStatus::Ok;
}

} // namespace bm
