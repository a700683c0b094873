// bmsimSessionAccuracy.h - bmsim bench --session --accuracy: what each session resolution buys in
// accuracy (bmReamingAccuracy.h) beside its frame times, as a table and a chart (Docs/RealTime.md,
// "The session's speed against accuracy").
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "bmScene.h"
#include "bmSessionBenchTable.h"
#include "bmVoxmap.h"

namespace bm::cli {

/// Runs the scene's offline reaming trial at each voxmap of `rows` (the session bench's cells of
/// `scene`, each with the shell scaled alike) and at referenceVoxmap (the converged reference),
/// compares each outcome with the reference's, and writes `out`/session_accuracy.csv and, in
/// builds with charts, `out`/session_speed_vs_accuracy.png: x the cell's worst frame p99 on the
/// incremental path (with the view when `view`), y the removed-volume error, each point labelled
/// with the face's depth and orientation errors and the seating's. bone(scene) builds the scene's
/// bone at its resolution. Prints each cell's line. Throws std::invalid_argument when the scene
/// is not a reaming scene.
void WriteSessionAccuracy(const Scene& scene, const std::vector<SessionBenchRow>& rows, bool view,
                          int referenceVoxmap, const std::function<Voxmap(const Scene&)>& bone,
                          const std::string& out, const std::string& machine,
                          const std::string& date);

} // namespace bm::cli
