// bmsimRunSession.h - `bmsim run SCENE --device scripted|touch [--mode feed|force|trajectory]`:
// the scene run through a haptic session (bmHapticSession.h) on its own thread at the haptic rate,
// instead of the offline feed trial. Called by bmsimRun.cxx when --mode is given or --device names
// a haptic device.
//
// Outputs in DIR: session.csv (the per-frame record) and summary.json (frame_ms_p50/p99/max,
// overruns, thrust/torque/feed statistics, forces sent, removed volume, the pause reason);
// --record FILE.h5|FILE.csv writes the record there too (for `bmsim replay`). All atomically.
#pragma once

#include <set>
#include <string>

#include "bmScene.h"
#include "bmsimArgs.h"

namespace bm::cli {

/// Valued options RunSessionScene reads (bmsimRun adds them to its parser):
///  --device scripted|touch   the haptic device (touch: OpenHaptics libHD.so, $BM_LIBHD overrides)
///  --mode feed|force|trajectory  scripted device: prescribed feed and speed (default), prescribed
///                            applied force, or a trajectory file
///  --force N                 force mode: applied force along the feed, N (default 2.0)
///  --trajectory FILE         trajectory mode: time_s,x_mm,y_mm,z_mm[,qw,qx,qy,qz] rows
///  --duration S              seconds of session time (default: feed mode the trial's depth,
///                            force mode 2 s, trajectory its length, touch 10 s)
///  --record FILE             also write the record to FILE (.h5 needs HDF5, else .csv)
///  --contact cutting|kim     contact model (default cutting, ours)
///  --rendering coupled|direct  (default coupled)
///  --rate HZ                 haptic rate (default 1000)
///  --overrun-limit N         pause after more than N overruns in 100 frames (default: touch 5,
///                            scripted never: a robot run reports its overruns instead)
extern const std::set<std::string> kSessionRunOptions;

/// Whether `bmsim run` should hand these arguments to RunSessionScene.
bool WantsSession(const ParsedArgs& args);

/// Runs the scene through a session; writes outDir/session.csv and outDir/summary.json. Returns the
/// exit code (0, or 1 when the session paused on a fault). Throws UsageError on bad options.
int RunSessionScene(const bm::Scene& scene, const ParsedArgs& args, const std::string& outDir);

} // namespace bm::cli
