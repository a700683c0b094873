// bmTouchProbe.h - whether a 3D Systems Touch can be opened, asked without risk to the caller.
//
// ProbeTouch() forks a child process that checks the HD library's file (bmSharedLibraryCheck.h),
// dlopen()s it, checks every entry point the Touch device calls (bm::hd::kRequiredSymbols: each
// exported, a function, defined by the library itself), calls hdInitDevice(HD_DEFAULT_DEVICE),
// reads the HD API's version and the device's model (hdGetString, when the library has it; a
// version older than bm::hd::kMinimumMajorVersion is refused), the nominal limits, then does what a
// session does next, at zero force: hdEnable(HD_FORCE_OUTPUT), a servo callback scheduled and run
// for 50 ticks (hdBeginFrame, the pose, HD_CURRENT_FORCE = 0, hdEndFrame), the scheduler stopped,
// and closes the device again with hdDisableDevice. The child reports each step and its answer
// through a pipe; a library that crashes (SIGSEGV, SIGBUS...), exits or hangs ends only the child,
// which is killed at the timeout, and the answer names the step it was in. The caller's thread
// waits at most the timeout (plus the few ms of reaping the child); run it off a GUI thread.
#pragma once

#include <string>

#include "bmDevice.h"

namespace bm {

struct TouchProbeResult {
  bool ready = false;  ///< a Touch was opened (and closed again)
  std::string message; ///< why not, naming the library and the step; "" when ready
  std::string library; ///< the library file checked ("" when the loader's cache found it)
  std::string version; ///< the HD API's version (hdGetString(HD_VERSION)); "" when not offered
  std::string model;   ///< the device model (hdGetString(HD_DEVICE_MODEL_TYPE)); "" if unknown
  /// The device's nominal limits when ready, the force at most the model's published peak force
  /// (bmHapticDeviceModel.h); else the Touch's published ones.
  DeviceLimits limits;
};

/// Probes the Touch (see the file comment). timeoutS: how long the child may take, s (default
/// 5; finite, 0 < timeoutS <= 600, else std::invalid_argument). libraryPath: "" = $BM_LIBHD or
/// "libHD.so", as bm::TouchDevice. Never throws for a fault of the library or the device: those
/// are in the result's message.
TouchProbeResult ProbeTouch(double timeoutS = 5.0, std::string libraryPath = "");

} // namespace bm
