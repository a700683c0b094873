// bmTouchDevice.h - the 3D Systems Touch through OpenHaptics' HD API, loaded at run time.
//
// Start(): check the library file (an ELF shared object for this machine, not truncated:
// bmSharedLibraryCheck.h), dlopen it (default "libHD.so"; BM_LIBHD in the environment or the
// constructor's path overrides), check every entry point it is to call (exported, a function,
// defined by the library itself), hdInitDevice(HD_DEFAULT_DEVICE) on a helper thread that is
// abandoned after `initTimeoutS` (a library that never returns cannot hang Start), refuse an HD
// API older than version 3 when the library says (hdGetString), hdEnable(HD_FORCE_OUTPUT), query
// the nominal limits (HD_NOMINAL_MAX_FORCE, HD_NOMINAL_MAX_STIFFNESS, HD_NOMINAL_MAX_DAMPING,
// HD_UPDATE_RATE), schedule an asynchronous servo callback at the highest priority, start the
// scheduler and wait for the callback's first pose sample. The callback runs at the device's rate
// on OpenHaptics' servo thread: in one hdBeginFrame/hdEndFrame it reads HD_CURRENT_POSITION,
// HD_CURRENT_TRANSFORM and HD_CURRENT_BUTTONS, writes HD_CURRENT_FORCE (the last force the session
// sent, through a locked DeviceStateBuffer), then checks hdGetError(). An error is latched and
// reported by the next Read() (the session then ramps the force to zero and pauses); a servo loop
// that has not delivered a new sample for `stallTimeoutS` reads as NoResponse. Stop(): zero force,
// stop the scheduler, unschedule, disable the device, close the library.
//
// The force limit is the smaller of the driver's nominal maximum and the model's published peak
// force (bmHapticDeviceModel.h), and the servo callback clamps every force it sends to it.
//
// A library that crashes still brings the process down here: ask bm::ProbeTouch()
// (bmTouchProbe.h), which runs the same steps (force output and the servo loop included, at zero
// force) in a child process, before starting a session on an unknown library; bmsim and the BM
// Session source do.
//
// Units: mm, N, N/mm, N s/mm (OpenHaptics' own units), Hz.
#pragma once

#include <atomic>
#include <chrono>
#include <string>

#include "bmDevice.h"
#include "bmHDApi.h"

namespace bm {

class TouchDevice final : public Device {
public:
  /// libraryPath: "" = $BM_LIBHD or "libHD.so". stallTimeoutS: no new servo sample for this
  /// long (s, default 0.05; finite, > 0) reads as NoResponse. initTimeoutS: how long Start()
  /// waits for hdInitDevice (s, default kInitTimeoutS; 0 < initTimeoutS <= 600). A value out of
  /// range throws std::invalid_argument naming it.
  explicit TouchDevice(std::string libraryPath = "", double stallTimeoutS = 0.05,
                       double initTimeoutS = kInitTimeoutS);
  ~TouchDevice() override;
  TouchDevice(const TouchDevice&) = delete;
  TouchDevice& operator=(const TouchDevice&) = delete;

  std::string Name() const override { return "touch"; }
  /// Limits queried at Start(), the force at most the model's published peak force
  /// (bmHapticDeviceModel.h) whatever the driver reports (before Start: the Touch's published
  /// ones).
  DeviceLimits Limits() const override { return Limits_; }
  /// Returns once the servo loop has delivered its first pose sample (waits at most
  /// kFirstSampleTimeoutS). Throws std::runtime_error naming the failing step (library, symbol,
  /// init, scheduler, no first sample); on a throw the device is closed again.
  void Start() override;
  /// How long Start() waits for the servo loop's first sample (s).
  static constexpr double kFirstSampleTimeoutS = 2.0;
  /// Default time Start() waits for hdInitDevice to return (s); OpenHaptics opens a Touch in
  /// about a second.
  static constexpr double kInitTimeoutS = 10.0;
  void Stop() override;
  DeviceStatus Read(DevicePose& pose) override;
  DeviceStatus Write(const Eigen::Vector3d& forceN) override;
  std::string LastError() const override;
  /// Servo callbacks run so far.
  uint64_t ServoTicks() const { return Ticks_.load(std::memory_order_relaxed); }

private:
  struct Api;
  static HDCallbackCode Servo(void* self);
  HDCallbackCode ServoTick();
  void Close();
  void InitDevice();

  std::string Path_;
  double StallTimeoutS_;
  double InitTimeoutS_;
  void* Lib_ = nullptr;
  Api* Api_ = nullptr;
  HHD Handle_ = hd::kInvalidHandle;
  HDSchedulerHandle Callback_ = 0;
  bool Scheduled_ = false, Running_ = false;
  DeviceLimits Limits_;
  std::string Model_; ///< hdGetString(HD_DEVICE_MODEL_TYPE), "" when not offered
  DeviceStateBuffer State_;
  DevicePose Last_;
  uint64_t LastSample_ = 0;
  std::chrono::steady_clock::time_point LastFresh_{};
  std::atomic<HDerror> Error_{hd::kSuccess};
  std::atomic<int> InternalError_{0};
  std::atomic<uint64_t> Ticks_{0};
};

} // namespace bm
