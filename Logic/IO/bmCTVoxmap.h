// bmCTVoxmap.h - a scene's CT bone as a voxmap, callable from code that must not see ITK headers
// (files using Eigen 3.4 must not mix in ITK's bundled Eigen 3.3): takes plain JSON and strings.
#pragma once

#include <array>
#include <functional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "bmVoxmap.h"

namespace bm {

/// The bone described by `ct` ({"ct": path | "phantom": name | "voxmap": file, ...import keys},
/// see bmImport.h VoxmapFromScene), paths relative to baseDir, resampled to `resolution` cells
/// along the region's longest side (0 = the description's own "resolution" or the importer's
/// default). progress(fraction, stage) may return false to cancel (throws bm::Cancelled).
/// noFinerThanCT: fewer cells where the CT's finest spacing is coarser than the voxel, though
/// voxels of at most toolVoxelMm (mm; 0: no such limit) (bmImport.h ImportOptions::noFinerThanCT;
/// default false). Throws std::runtime_error naming the problem.
Voxmap MakeCTVoxmap(const nlohmann::json& ct, const std::string& baseDir, int resolution,
                    const std::function<bool(double, const std::string&)>& progress = {},
                    bool noFinerThanCT = false, double toolVoxelMm = 0);

/// A CT volume held in memory as plain arrays (a VTK image's point scalars): values[i + nx (j +
/// ny k)], HU unless the import options say otherwise. World position (mm) of voxel (i, j, k):
/// origin + D (i sx, j sy, k sz), D = direction (row-major 3 x 3, its columns the image axes).
struct CTVolumeView {
  const float* values = nullptr;
  std::array<int, 3> dims{0, 0, 0};
  std::array<double, 3> spacing{1, 1, 1}; ///< mm
  std::array<double, 3> origin{0, 0, 0};  ///< world mm of voxel (0, 0, 0)
  std::array<double, 9> direction{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::string source = "image data"; ///< what the volume is, for the report
  /// How the values were stored before they became floats (the intensity evidence,
  /// bmIntensityMapping.h): bits per value (0 = unknown) and whether they were integers.
  int storedBits = 0;
  bool storedInteger = false;
};

/// The bone of an in-memory CT volume as a voxmap: the import of MakeCTVoxmap (options: the
/// import keys of a scene's bone, bmImport.h ImportOptionsFromJson; any "ct" key is ignored).
/// The values go through the same intensity decision as a file's (bmCTReader.h
/// ApplyIntensityDecision): values that are clearly not HU (a windowed 8-bit image) are refused
/// unless the options say how to read them ("rawThreshold" or "huMapping").
/// `report` (optional) receives the import's summary. Throws std::runtime_error naming the
/// problem (empty volume, spacing <= 0, non-finite values, not HU, no bone).
Voxmap MakeCTVoxmapFromVolume(const CTVolumeView& volume, const nlohmann::json& options,
                              int resolution,
                              const std::function<bool(double, const std::string&)>& progress = {},
                              std::string* report = nullptr);

/// Write an in-memory CT volume as a MetaImage (.mha) file a scene's "ct" key can name. Throws
/// std::runtime_error when it cannot be written.
void SaveCTVolume(const CTVolumeView& volume, const std::string& path);

} // namespace bm
