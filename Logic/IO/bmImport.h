// bmImport.h - the whole path from a CT to a voxmap, as `bmsim import`, scenes and the GUI use it:
// read (bmCTReader) -> crop to the region of interest -> segment (bmBoneSegmenter) -> resample
// into the voxmap (bmVoxmapResampler) [-> save atomically (bmVoxmapFile)].
//
// Every input is checked before anything is written: ImportToFile checks the output path first,
// imports, and saves only when all steps succeeded (temporary file, then rename), so a refused
// input or a cancel leaves no file behind.
#pragma once

#include "bmBoneSegmenter.h"
#include "bmCTReader.h"
#include "bmProgress.h"
#include "bmVoxmap.h"
#include "bmVoxmapResampler.h"

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace bm {

struct ImportOptions {
  ReadOptions read;                 ///< series choice, memory limit (also used for the later steps)
  SegmentationOptions segmentation; ///< threshold (HU), seed (mm), holes
  /// Region of interest, world mm. Without one: the bounding box of the segmented bone grown by
  /// half a CT voxel (the reach of the resampler's interpolation), within the CT.
  std::optional<Box3> roiMm;
  /// Voxmap resolution: cells along the ROI's longest axis (Docs/CostModel.md section 1).
  /// Default 256.
  int resolution = 256;
  /// Fewer cells when the CT's finest spacing is coarser than the voxel: at most floor(longest
  /// side / finest spacing) cells (bmVoxmapResampler.h CellsNoFinerThan), so the voxmap models no
  /// detail the CT did not resolve (a haptic session's grid). Default false.
  bool noFinerThanCT = false;
  /// With noFinerThanCT: voxels of at most this size (mm) even where the CT's are coarser, so a
  /// small tool is still resolved (bmSessionGrid.h ToolVoxelMm). 0 (default): no such limit.
  double toolVoxelMm = 0;
  MaterialMapping material;
  int threads = 0; ///< resampling threads (0 = all cores)
};

struct ImportResult {
  Voxmap voxmap;
  // What was read (the CT's voxels are released once segmented).
  std::string source, format, modality, seriesUID, seriesDescription, transferSyntax;
  int numFiles = 0;
  std::array<int, 3> ctSize{0, 0, 0};
  std::array<double, 3> ctSpacing{0, 0, 0}; ///< mm
  Box3 ctBounds;                            ///< world mm
  float huMin = 0, huMax = 0;
  std::vector<std::string> warnings;
  std::vector<std::string> notes; ///< how the series or file was chosen (CTImage::notes)
  IntensityMapping intensity;     ///< what the CT's values meant (bmIntensityMapping.h)
  // Segmentation.
  /// Bone volume at CT resolution (sum of fractions; with a ROI, of the parts of the voxels
  /// inside it), mm^3.
  double segmentedVolumeMm3 = 0;
  /// Volume of the CT voxels at or above the threshold before components, separation and hole
  /// filling (in the cropped region), mm^3: what the steps changed shows against it.
  double thresholdVolumeMm3 = 0;
  int numComponents = 0;
  int holesFilled = 0;
  double separationDepthMm = 0; ///< erosion that split touching bones, mm (0: none needed)
  Box3 roi;                     ///< the box the voxmap covers, world mm
  /// Human-readable summary (several lines): modality, size, spacing, HU range, bone volume.
  std::string Report() const;
};

/// Import a CT (folder or file) into a voxmap. Throws std::runtime_error (bad input), Cancelled.
ImportResult ImportVoxmap(const std::string& input, const ImportOptions& options = {},
                          const Progress& progress = {});
/// The same from a CT already in memory (e.g. a phantom made by MakePhantomCT).
ImportResult ImportVoxmap(CTImage ct, const ImportOptions& options, const Progress& progress = {});
/// Import and save to `output` (.nrrd or .mha; atomic). The output path is checked first.
ImportResult ImportToFile(const std::string& input, const std::string& output,
                          const ImportOptions& options = {}, const Progress& progress = {});

/// Check that `output` can receive a voxmap (.nrrd/.mha, its folder exists); throws otherwise.
void CheckVoxmapOutputPath(const std::string& output);

/// The box of a region of interest given as [x0, y0, z0, x1, y1, z1] (world mm, the one ROI
/// order of the CLI, scenes and the plugin). Throws std::runtime_error naming `what` when the
/// box is inverted or empty along an axis (x1 <= x0, ...) or a value is not finite.
Box3 RoiFromCorners(const std::vector<double>& corners, const std::string& what);

/// World points (mm) from text "x,y,z" or several "x,y,z;x,y,z" (a multiple of three numbers,
/// separated by commas, semicolons or spaces). Throws std::runtime_error naming `what`.
std::vector<std::array<double, 3>> ParsePointsMm(const std::string& text, const std::string& what);

/// An oriented box from text "CX,CY,CZ,HX,HY,HZ[,RX,RY,RZ]": centre and half sizes (mm),
/// rotation about x, y, z (degrees, bmBoxROI.h). Throws std::runtime_error naming `what`.
OrientedBox OrientedBoxFromText(const std::string& text, const std::string& what);

/// Options from a scene's bone description (all keys optional):
///   "threshold": HU, "seed": [x, y, z] mm (the bone to keep), "exclude": [[x, y, z], ...] mm
///   (bones to drop, separated from the kept one across joint spaces), "exclude_heads":
///   [{"centre_mm": [x, y, z], "radius_mm": r, "shell_mm": s, "socket_centre_mm": [x, y, z],
///   "socket_radius_mm": rs}, ...] (a humeral head cut off its glenoid, left out:
///   bmExcludedHead.h; the socket optional), "roi": [x0, y0, z0, x1,
///   y1, z1] mm (inverted: an error), "box": {"centre": [x, y, z] mm, "halfSizes": [a, b, c]
///   mm, "rotation": [rx, ry, rz] deg} (an oriented box, bmBoxROI.h), "resolution": N, "series":
///   SeriesInstanceUID, "noFinerThanCT": bool (fewer cells where the CT's spacing
///   is coarser), "toolVoxelMm": mm (> 0; with it, voxels no coarser than this),
///   "keepAllComponents": bool, "fillHoles": bool (cavities, default true),
///   "closingRadius": voxels (default 1), "maxHoleVolume": mm^3, "separationDepth": mm (default 8),
///   "maxMemoryMB": MiB, "corticalHU": HU, "rawThreshold": value in the file's units (values
///   not HU), "huMapping": [slope, intercept] (HU = slope x value + intercept),
///   "allowOutsideData": bool (Docs/CTImport.md).
/// Throws std::runtime_error naming a key of the wrong type or value.
ImportOptions ImportOptionsFromJson(const nlohmann::json& bone);

/// The inverse for what a user sets when choosing how a CT is read (the plan's step scenes carry
/// the settings the plan was made with): "threshold" (or "rawThreshold"), "huMapping",
/// "series", "seed", "exclude", "exclude_heads", "roi", "box", "keepAllComponents", "fillHoles",
/// "resolution",
/// "allowOutsideData", "maxMemoryMB" when set. ImportOptionsFromJson(ImportOptionsToJson(o))
/// gives back those fields of o.
nlohmann::json ImportOptionsToJson(const ImportOptions& options);

/// A scene's bone as a voxmap. `bone` holds exactly one source, paths relative to baseDir:
///   {"voxmap": "file.nrrd"} (loaded as is), {"ct": "folder-or-file", ...ImportOptions keys} or
///   {"phantom": "glenoid"|"block", ...ImportOptions keys} (the phantom CT is made in memory).
Voxmap VoxmapFromScene(const nlohmann::json& bone, const std::string& baseDir,
                       const Progress& progress = {});

} // namespace bm
