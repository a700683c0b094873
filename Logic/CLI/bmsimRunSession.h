// bmsimRunSession.h - `bmsim run SCENE --device scripted|touch [--mode
// feed|force|trajectory|hand]`: the scene (a block, a CT or phantom scene such as glenoid or skull)
// run through a haptic session (bmHapticSession.h) on its own thread at the haptic rate, instead of
// the offline feed trial. Called by bmsimRun.cxx when --mode is given or --device names a haptic
// device.
//
// Outputs in DIR: session.csv (the per-frame record) and summary.json (frame_ms_p50/p99/max,
// overruns, thrust/torque/feed statistics, forces sent, force scale, removed volume, the pause
// reason); --record FILE.h5|FILE.csv writes the record there too (for `bmsim replay`). All
// atomically, and every output path is checked before the session starts.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "bmInputFiles.h"
#include "bmScene.h"
#include "bmVoxmap.h"
#include "bmsimArgs.h"

namespace bm::cli {

/// Declares the options RunSessionScene reads (bmsim run adds them to its own):
///  --device scripted|touch   the haptic device (touch: OpenHaptics libHD.so, $BM_LIBHD overrides)
///  --mode feed|force|trajectory|hand, --force N, --force-scale S, --seed N, --trajectory FILE,
///  --duration S, --record FILE, --contact cutting|kim, --rendering coupled|direct, --rate HZ,
///  --overrun-limit N (each described in its --help line; the session is built by
///  bm::BuildSession, bmSessionBuilder.h).
void SessionRunOptions(ParsedArgs& p);

/// Whether `bmsim run` should hand these arguments to RunSessionScene.
bool WantsSession(const ParsedArgs& args);

/// The scene's bone: a block, or a CT / phantom / saved voxmap through the IO library (throws
/// std::runtime_error when this build has no IO library).
Voxmap SceneBone(const bm::Scene& scene);

/// Throws UsageError naming `what` and `path` when the output could not be created there: a file
/// whose folder is missing or not writable, or that is an existing folder; a folder (isFolder,
/// created with its parents) that is an existing file or whose nearest existing ancestor is not
/// writable. Creates nothing.
void CheckWritableOutput(const std::string& what, const std::string& path, bool isFolder);

/// The files a run of `scene` reads (bmInputFiles.h): the scene file named on the command line,
/// the scene's CT or voxmap (with a detached data file or DICOM folder) and --trajectory.
InputFiles RunInputs(const bm::Scene& scene, const ParsedArgs& args);

/// Throws std::runtime_error when an output of a run names one of its inputs, or --record is one
/// of the files the run writes into outDir (`written`, e.g. session.csv and summary.json).
void CheckRunOutputs(const bm::Scene& scene, const ParsedArgs& args, const std::string& outDir,
                     const std::vector<std::string>& written);

/// Runs the scene through a session; writes outDir/session.csv and outDir/summary.json. Returns the
/// exit code (0, or 1 when the session paused on a fault). Throws UsageError on bad options.
int RunSessionScene(const bm::Scene& scene, const ParsedArgs& args, const std::string& outDir);

} // namespace bm::cli
