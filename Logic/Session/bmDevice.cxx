#include "bmDevice.h"

namespace bm {

const char* ToString(DeviceStatus s) {
  switch (s) {
  case DeviceStatus::Ok:
    return "ok";
  case DeviceStatus::Error:
    return "error";
  case DeviceStatus::NoResponse:
    return "no response";
  }
  return "?";
}

void DeviceStateBuffer::PutPose(const DevicePose& p) {
  std::lock_guard<std::mutex> lock(Mutex_);
  Pose_ = p;
  ++Sample_;
}

Eigen::Vector3d DeviceStateBuffer::GetForce() const {
  std::lock_guard<std::mutex> lock(Mutex_);
  return Force_;
}

bool DeviceStateBuffer::TryGetPose(DevicePose& pose, uint64_t& sample) const {
  std::unique_lock<std::mutex> lock(Mutex_, std::try_to_lock);
  if (!lock.owns_lock())
    return false;
  pose = Pose_;
  sample = Sample_;
  return true;
}

void DeviceStateBuffer::GetPose(DevicePose& pose, uint64_t& sample) const {
  std::lock_guard<std::mutex> lock(Mutex_);
  pose = Pose_;
  sample = Sample_;
}

bool DeviceStateBuffer::TryPutForce(const Eigen::Vector3d& f) {
  std::unique_lock<std::mutex> lock(Mutex_, std::try_to_lock);
  if (!lock.owns_lock())
    return false;
  Force_ = f;
  return true;
}

void DeviceStateBuffer::PutForce(const Eigen::Vector3d& f) {
  std::lock_guard<std::mutex> lock(Mutex_);
  Force_ = f;
}

} // namespace bm
