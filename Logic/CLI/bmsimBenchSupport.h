// bmsimBenchSupport.h - what the modes of `bmsim bench` (bmsimBench.cxx, bmsimBenchView.cxx,
// bmsimBenchSession.cxx) share: resolution lists from the command line, the machine's and the
// OpenCL device's names for the results' notes, and the scene's bone.
#pragma once

#include <string>
#include <vector>

#include "bmScene.h"
#include "bmVoxmap.h"
#include "bmsimArgs.h"

namespace bm::cli {

/// The resolutions option `name` lists (comma-separated, each in 8..4096), or `def` when it is not
/// given. Throws UsageError naming the option when an entry is not such a resolution or the list
/// is empty.
std::vector<int> Resolutions(const ParsedArgs& p, const std::string& name, std::vector<int> def);

/// This machine's CPU model and its logical cores, for the results' notes.
std::string MachineName();

/// The OpenCL device `choice` picks, with its platform, or why there is none. Call it only after
/// the grid's cells ran: they fork, and a parent that opened OpenCL must not.
std::string OpenCLDeviceName(const std::string& choice);

/// The scene's bone for the bench (bm::MakeSceneBone; without BMIO, the glenoid phantom's analytic
/// bone). Not bmsimRunSession.h's SceneBone: bmsim run's, with a progress bar while a CT imports.
bm::Voxmap BenchSceneBone(const bm::Scene& scene);

} // namespace bm::cli
