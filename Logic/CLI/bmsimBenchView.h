// bmsimBenchView.h - `bmsim bench --view`: the live view of the cut bone during a reaming session
// (builds with VTK only: the view's surface, bm::BoneSurface).
#pragma once

#include "bmsimArgs.h"

namespace bm::cli {

#ifdef BM_WITH_REPORT
/// Runs the scene's scripted feed once without and once with the live view refreshing, for each
/// voxmap (and shell) asked; prints the refresh and haptic frame times and writes view.csv in
/// --out. Returns the exit code.
int ViewBench(const ParsedArgs& p);
#endif

} // namespace bm::cli
