// bmResources.h - where the module's resources (built-in scenes, benchmark tables, calibration
// data) are found at run time, in a build tree and in an installed prefix alike.
//
// Order: the environment variable BM_RESOURCE_DIR when set and not empty; else the folder
// share/BoneMachining found above the binary that holds this code (bmsim in <prefix>/bin, the
// plugin in <prefix>/lib/paraview-plugins/BoneMachining); else the source tree's Resources/ (a
// build tree, compiled in as BM_SOURCE_RESOURCE_DIR). `cmake --install` copies Resources/Scenes,
// Resources/Benchmark and Resources/Calibration to <prefix>/share/BoneMachining.
#pragma once

#include <filesystem>

namespace bm {

/// The resource root: holds Scenes/, Benchmark/ and Calibration/. Never empty; the folder may not
/// exist when the installation is incomplete (callers report the missing file by its full path).
std::filesystem::path ResourceDir();

/// ResourceDir() / relative.
std::filesystem::path ResourcePath(const std::filesystem::path& relative);

} // namespace bm
