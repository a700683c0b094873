// bmsimBenchSession.h - `bmsim bench --session`: a haptic session's frame time on a scene in a
// hand-like trial, the incremental path against the full pass.
#pragma once

#include "bmsimArgs.h"

namespace bm::cli {

/// Runs the session bench on the scene --session names; prints each run's frame times and
/// checksum and writes session.csv (and, with --accuracy, the session accuracy) in --out. Returns
/// the exit code.
int SessionBench(const ParsedArgs& p);

} // namespace bm::cli
