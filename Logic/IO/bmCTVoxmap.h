// bmCTVoxmap.h - a scene's CT bone as a voxmap, callable from code that must not see ITK headers
// (files using Eigen 3.4 must not mix in ITK's bundled Eigen 3.3): takes plain JSON and strings.
#pragma once

#include <functional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "bmVoxmap.h"

namespace bm {

/// The bone described by `ct` ({"ct": path | "phantom": name | "voxmap": file, ...import keys},
/// see bmImport.h VoxmapFromScene), paths relative to baseDir, resampled to `resolution` cells
/// along the region's longest side (0 = the description's own "resolution" or the importer's
/// default). progress(fraction, stage) may return false to cancel (throws bm::Cancelled).
/// Throws std::runtime_error naming the problem.
Voxmap MakeCTVoxmap(const nlohmann::json& ct, const std::string& baseDir, int resolution,
                    const std::function<bool(double, const std::string&)>& progress = {});

} // namespace bm
