#include "bmProgrammableDevice.h"

namespace bm {

void ProgrammableDevice::Advance(double timeS, double dtS) {
  (void)timeS;
  Dt_ = dtS;
}

DeviceStatus ProgrammableDevice::Read(DevicePose& pose) {
  uint64_t sample = 0;
  State_.TryGetPose(Target_, sample); // busy: keep the previous pose (the GUI is writing one)
  const double v = MaxSpeed_.load(std::memory_order_relaxed);
  const Eigen::Vector3d from = Last_.positionMm;
  Last_ = Target_;
  if (Have_ && v > 0 && Target_.positionMm.allFinite()) {
    const Eigen::Vector3d gap = Target_.positionMm - from;
    const double n = gap.norm(), step = v * Dt_;
    if (n > step)
      Last_.positionMm = from + gap * (step / n);
  }
  Have_ = true;
  pose = Last_;
  return DeviceStatus::Ok;
}

DeviceStatus ProgrammableDevice::Write(const Eigen::Vector3d& forceN) {
  State_.TryPutForce(forceN); // display only: a busy buffer just shows last frame's force
  return DeviceStatus::Ok;
}

} // namespace bm
