// bmVoxmapFile.h - save and load a voxmap (also a partly cut one) as NRRD or MetaImage.
//
// File layout: a 3-D image of 2 float32 components per voxel, world-axis aligned (identity
// direction), isotropic spacing (mm), origin = world mm of the centre of voxel (0, 0, 0) (the ITK,
// NRRD and MetaImage convention, so 3D Slicer or ParaView show it in place):
//   component 0 = bone fraction = fill / Voxmap::kFull (exact in float32 for every fill in
//                 [-kFull, kFull]; fills below -kFull, i.e. more than a whole voxel over-removed,
//                 are saved as -kFull: void either way);
//   component 1 = material scale (1 = cortical).
// Key/value fields bm_voxmap_version, bm_spacing and bm_origin (hexadecimal floating point) keep
// the geometry bit-exact whatever decimal precision the format writes. NRRD files are
// gzip-compressed (cut voxmaps are mostly runs of 0 and 1), MetaImage files zlib-compressed.
//
// Saving is atomic: the file is written under a temporary name in the target folder and renamed
// over the target only when complete, so a crash or cancel never leaves a half-written voxmap.
// Loading also accepts a 1-component image (bone fraction 0..1, material 1).
#pragma once

#include "bmProgress.h"
#include "bmVoxmap.h"

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bm {

/// Save to path (.nrrd or .mha; other extensions are refused with std::runtime_error).
/// `fields`: extra key/value fields written into the header (e.g. bm_intensity_mapping).
void SaveVoxmap(const Voxmap& voxmap, const std::string& path, const Progress& progress = {},
                const std::vector<std::pair<std::string, std::string>>& fields = {});

/// Load a voxmap saved by SaveVoxmap (or a compatible image). The header is checked first
/// (bmHeaderCheck.h, with 2 values per voxel allowed). Throws std::runtime_error naming the file
/// on a missing or unreadable file, another extension than .nrrd/.nhdr/.mha/.mhd, a header the
/// check refuses, an oblique (non-identity direction) or anisotropic image, more than 2
/// components, a non-finite bone fraction, or a material scale outside [0, 10] (NaN, infinite,
/// negative) naming the voxel.
Voxmap LoadVoxmap(const std::string& path, const Progress& progress = {});

/// The trial a session's bone was cut on: its entry point (world mm, where the axis enters the
/// bone), axis (world, unit, from the bone out toward the shank) and the tool that cut it (a
/// scene's "tool" object as JSON text; empty: not saved). Saved in the voxmap file's header (fields
/// bm_trial_entry_mm and bm_trial_axis, hexadecimal floating point, so exact; bm_tool), so that a
/// session started again from the file goes on at the same place with the same tool.
struct VoxmapTrial {
  std::array<double, 3> entryMm{0, 0, 0};
  std::array<double, 3> axis{0, 0, 1};
  std::string toolJson;
};

/// The header fields that save `trial` (pass them to SaveVoxmap's `fields`).
std::vector<std::pair<std::string, std::string>> VoxmapTrialFields(const VoxmapTrial& trial);

/// The trial saved in a voxmap file's header, reading only the header (checked as LoadVoxmap
/// checks it); the axis is normalised. nullopt when the file carries none (a voxmap from bmsim
/// import, or saved before trials were). Throws std::runtime_error naming the file as LoadVoxmap
/// does, and when the trial's fields are incomplete, not numbers, non-finite or a zero axis.
std::optional<VoxmapTrial> LoadVoxmapTrial(const std::string& path);

} // namespace bm
