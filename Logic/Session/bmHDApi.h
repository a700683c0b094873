// bmHDApi.h - the part of OpenHaptics' HD API (3D Systems) that the Touch device uses, declared
// here from the OpenHaptics programmer's guide and API reference so that nothing proprietary is
// needed to build: the library (libHD.so) is loaded at run time (bmTouchDevice.h), and a small
// fake built by the tests implements the same functions.
#pragma once

#include <climits>

extern "C" {
typedef unsigned int HDuint;
typedef unsigned char HDboolean;
typedef unsigned long HDulong;
typedef unsigned short HDushort;
typedef int HDint;
typedef double HDdouble;
typedef unsigned int HDerror;
typedef unsigned int HDenum;
typedef const char* HDstring;
typedef unsigned int HHD;
typedef unsigned long HDSchedulerHandle;
typedef unsigned int HDCallbackCode;
typedef HDCallbackCode (*HDSchedulerCallback)(void* userData);

typedef struct {
  HDerror errorCode;     // HD_ error code
  int internalErrorCode; // the device's own code
  HHD hHD;               // device current when the error occurred
} HDErrorInfo;
}

namespace bm::hd {
constexpr HDCallbackCode kCallbackDone = 0;     // HD_CALLBACK_DONE
constexpr HDCallbackCode kCallbackContinue = 1; // HD_CALLBACK_CONTINUE
constexpr HHD kInvalidHandle = 0xFFFFFFFF;      // HD_INVALID_HANDLE
constexpr HDushort kMaxSchedulerPriority = USHRT_MAX;

// Error codes
constexpr HDerror kSuccess = 0x0000;
constexpr HDerror kInvalidEnum = 0x0100, kInvalidValue = 0x0101, kInvalidOperation = 0x0102,
                  kInvalidInputType = 0x0103, kBadHandle = 0x0104;
constexpr HDerror kWarmMotors = 0x0200, kExceededMaxForce = 0x0201,
                  kExceededMaxForceImpulse = 0x0202, kExceededMaxVelocity = 0x0203,
                  kForceError = 0x0204;
constexpr HDerror kDeviceFault = 0x0300, kDeviceAlreadyInitiated = 0x0301, kCommError = 0x0302,
                  kCommConfigError = 0x0303, kTimerError = 0x0304;
constexpr HDerror kIllegalBegin = 0x0400, kIllegalEnd = 0x0401, kFrameError = 0x0402;
constexpr HDerror kInvalidPriority = 0x0500, kSchedulerFull = 0x0501;
constexpr HDerror kInvalidLicense = 0x0600;
/// Not an OpenHaptics code: the Touch device's own latch for a non-finite position or transform.
constexpr HDerror kNonFinitePose = 0xFF01;

// Parameters
constexpr HDenum kCurrentButtons = 0x2000;
constexpr HDenum kCurrentPosition = 0x2050;     // 3 doubles, mm
constexpr HDenum kCurrentTransform = 0x2052;    // 16 doubles, column-major, translation in mm
constexpr HDenum kUpdateRate = 0x2600;          // int, Hz
constexpr HDenum kNominalMaxStiffness = 0x2602; // N/mm
constexpr HDenum kNominalMaxForce = 0x2603;     // N
constexpr HDenum kNominalMaxDamping = 0x2609;   // N s/mm
constexpr HDenum kCurrentForce = 0x2700;        // 3 doubles, N
constexpr HDenum kForceOutput = 0x4000;         // hdEnable capability
constexpr HDenum kVersion = 0x2500;             // hdGetString: the HD API's version, "3.4.0"
constexpr HDenum kDeviceModelType = 0x2501;     // hdGetString: the device model, "Touch"

/// Entry points the Touch device calls (bmTouchDevice.cxx), all required; the library's exported
/// function symbols are checked against this list before any is called.
inline constexpr const char* kRequiredSymbols[] = {
    "hdInitDevice",     "hdDisableDevice", "hdMakeCurrentDevice",    "hdBeginFrame",
    "hdEndFrame",       "hdEnable",        "hdGetDoublev",           "hdGetIntegerv",
    "hdSetDoublev",     "hdGetError",      "hdScheduleAsynchronous", "hdUnschedule",
    "hdStartScheduler", "hdStopScheduler"};
/// Optional entry point: HDstring hdGetString(HDenum), for kVersion and kDeviceModelType.
inline constexpr const char* kVersionSymbol = "hdGetString";
/// Oldest HD API major version accepted (OpenHaptics 3 drives the Touch).
constexpr int kMinimumMajorVersion = 3;

/// Readable name of an HD error code.
const char* ErrorName(HDerror code);
} // namespace bm::hd
