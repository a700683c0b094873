// bmTestGlenoidHand.h - the scripted hand on the analytic glenoid (bmTestGlenoid.h) for the
// session tests: its device and its session, one definition for the tests that run it.
#pragma once

#include <cstddef>
#include <cstdint>

#include "bmHapticSession.h"
#include "bmMachiningSetup.h"
#include "bmScriptedDevice.h"

namespace bmtest {

/// The scripted hand on the analytic glenoid: a firm push on the Touch (2.5 N, through a force
/// scale of 50) with 0.1 N of tremor, from 1 mm above the face along the scene's axis.
inline bm::ScriptedDeviceOptions GlenoidHand(const bm::MachiningSetup& setup) {
  bm::ScriptedDeviceOptions d;
  d.mode = bm::ScriptMode::Hand;
  d.startMm = {0, 0, 1.0}; // the face 1 mm below the reamer's foremost ring
  d.rotation = setup.ToolRotation();
  d.appliedForceN = 2.5; // a firm push on the Touch
  d.handTremorN = 0.1;
  d.handRampS = 0.1;
  return d;
}

/// A session of `frames` frames back to back at the reamer's 500 rpm, every frame recorded, the
/// hand's force scale of 50, no overrun rule.
inline bm::SessionOptions GlenoidHandSession(int64_t frames) {
  bm::SessionOptions o;
  o.realTime = false;
  o.overrunLimit = -1;
  o.maxFrames = frames;
  o.speedRpm = 500;
  o.recordCapacity = size_t(frames) + 16;
  o.proxy.coupling.forceScale = 50;
  return o;
}

} // namespace bmtest
