// bmDevice.h - a haptic device as the session sees it: pose in, force out, nominal limits.
//
// The session thread calls, once per frame and only from that thread: Advance(t, dt) (scripted
// devices move; real devices ignore it), Read(pose), then Write(force). A device that runs its own
// servo thread (the Touch) or whose pose another thread sets (the GUI's mouse proxy) exchanges
// pose and force through a DeviceStateBuffer: a locked snapshot, as iMSTK's device client keeps
// one, read with try_lock so the haptic thread never waits (it keeps the previous pose instead).
//
// Units: position mm, force N, stiffness N/mm, damping N s/mm, rate Hz. Frames: the device's own
// (the session maps them to world, bmHapticSession.h).
#pragma once

#include <cstdint>
#include <mutex>
#include <string>

#include <Eigen/Core>

namespace bm {

/// Nominal limits; defaults are the 3D Systems Touch (Docs/Interaction.md section 5).
struct DeviceLimits {
  double maxForceN = 3.3;           ///< largest force the device may be sent, N
  double maxStiffnessNPerMm = 0.4;  ///< nominal maximum renderable stiffness, N/mm
  double maxDampingNsPerMm = 0.004; ///< nominal maximum damping, N s/mm (4 N s/m)
  double workspaceRadiusMm = 75;    ///< usable workspace radius, mm
  double rateHz = 1000;             ///< servo rate, Hz
};

struct DevicePose {
  Eigen::Vector3d positionMm = Eigen::Vector3d::Zero();   ///< mm, device frame
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity(); ///< stylus -> device frame
  uint32_t buttons = 0;                                   ///< bit i = button i+1 pressed
};

enum class DeviceStatus {
  Ok,
  Error,      ///< the device reported an error (LastError() says which)
  NoResponse, ///< the device stopped answering (no new servo sample)
};
const char* ToString(DeviceStatus s);

class Device {
public:
  virtual ~Device() = default;
  /// Short name ("scripted", "touch", "programmable").
  virtual std::string Name() const = 0;
  /// Nominal limits (the Touch queries them from the driver at Start()).
  virtual DeviceLimits Limits() const = 0;
  /// Opens the device and enables force output. Throws std::runtime_error on failure. Default:
  /// nothing.
  virtual void Start() {}
  /// Sends zero force and closes the device; safe to call twice. Default: nothing.
  virtual void Stop() {}
  /// Moves a scripted device to session time timeS (s) over a frame of dtS (s). Default: nothing.
  virtual void Advance(double timeS, double dtS) {
    (void)timeS;
    (void)dtS;
  }
  /// The latest pose. On Error/NoResponse `pose` keeps its previous value.
  virtual DeviceStatus Read(DevicePose& pose) = 0;
  /// Sends a force (N, device frame). The session only ever sends finite forces within Limits().
  virtual DeviceStatus Write(const Eigen::Vector3d& forceN) = 0;
  /// Description of the last error ("" when none).
  virtual std::string LastError() const { return {}; }
};

/// Pose/force exchange between a device thread (servo callback, GUI) and the haptic thread.
/// Every method is thread-safe; the Try* methods never block.
class DeviceStateBuffer {
public:
  /// Device side: store a new pose sample (counter advances by one).
  void PutPose(const DevicePose& p);
  /// Device side: the force to output now (N), the last one the session wrote.
  Eigen::Vector3d GetForce() const;
  /// Haptic side: copy the latest pose if the lock is free; returns false (pose untouched) if busy.
  /// sample receives the pose counter (it stops advancing when the device stops answering).
  bool TryGetPose(DevicePose& pose, uint64_t& sample) const;
  /// Blocking copy of the latest pose and its counter (used when starting, never in the loop).
  void GetPose(DevicePose& pose, uint64_t& sample) const;
  /// Haptic side: store the force to output if the lock is free; false if busy (retry next frame).
  bool TryPutForce(const Eigen::Vector3d& f);
  /// Blocking set of the force (used when stopping: zero force must get through).
  void PutForce(const Eigen::Vector3d& f);

private:
  mutable std::mutex Mutex_;
  DevicePose Pose_;
  uint64_t Sample_ = 0;
  Eigen::Vector3d Force_ = Eigen::Vector3d::Zero();
};

} // namespace bm
