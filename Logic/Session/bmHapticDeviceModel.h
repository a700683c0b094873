// bmHapticDeviceModel.h - what a haptic device model can render at most, as its maker publishes
// it, independent of what its driver reports: a driver that claims 10^6 N must not be sent more
// than the device's own peak force.
//
// Models (matched by name, case-insensitively, in the string OpenHaptics' hdGetString
// (HD_DEVICE_MODEL_TYPE) returns): Touch / PHANTOM Omni 3.3 N, Touch X / PHANTOM Desktop 7.9 N,
// PHANTOM Premium 1.5 High Force 37.5 N, PHANTOM Premium 3.0 22 N, PHANTOM Premium 1.0 / 1.5
// 8.5 N. Any other name (or none) is taken for a Touch, the device this module drives: 3.3 N.
#pragma once

#include <string>

#include "bmDevice.h"

namespace bm {

/// The model's published peak force, N (see above; unknown: the Touch's 3.3 N).
double PublishedMaxForceN(const std::string& model);

/// `reported` (the driver's nominal limits) with the force limit at most the model's published
/// peak force; a non-finite or non-positive reported force becomes the published one.
DeviceLimits CapToModel(DeviceLimits reported, const std::string& model);

} // namespace bm
