// bmBoneSegmenter.h - bone from a CT in Hounsfield units, with ITK filters.
//
// Steps (each reported through Progress):
//  1. threshold: voxels with HU >= thresholdHU are bone (default 200 HU: above soft tissue and
//     marrow, below cancellous bone of ordinary density; InVesalius' bone preset is 226 HU);
//  2. components (26-connected, itk::ConnectedComponentImageFilter + RelabelComponentImageFilter):
//     keep the component holding the seed point, else the largest, else (keepAllComponents) all;
//  3. fill interior holes: background components (6-connected) that do not touch the image border,
//     are at most maxHoleVolumeMm3 and whose mean HU is at least holeMinMeanHU become bone. Marrow
//     and low-density cancellous bone inside a cortical shell are bone; air cells (mastoid,
//     sinuses, mean HU far below 0) and large cavities (the cranial cavity, above the volume limit)
//     are not;
//  4. partial volume: bone fraction per voxel. Voxels away from the bone surface are 1 (bone) or 0;
//     a voxel within one voxel of the surface gets (HU - soft) / (bone - soft) clamped to [0, 1],
//     with soft = mean HU of the pure non-bone voxels and bone = the highest HU of the pure bone
//     voxels within 2 voxels (so a voxel half filled with cortical bone counts half, not all, as a
//     threshold would make it). Filled-hole voxels are 1.
//
// The HU of the bone at each bone voxel (boneHU) is kept for the material scale: inside the bone
// its own HU, at the surface the bone reference above (its own HU is diluted by the soft tissue).
#pragma once

#include "bmCTImage.h"
#include "bmProgress.h"

#include <array>
#include <cstdint>
#include <optional>

namespace bm {

struct SegmentationOptions {
  /// Bone threshold, HU (voxels at or above are bone).
  float thresholdHU = 200.0f;
  /// World point (mm): keep the connected component containing it (or touching it within one
  /// voxel). Without a seed the largest component is kept.
  std::optional<std::array<double, 3>> seedMm;
  /// Keep every component above the threshold (ignored when a seed is given).
  bool keepAllComponents = false;
  /// Fill interior holes (see above).
  bool fillHoles = true;
  /// Largest hole filled, mm^3 (default 20 cm^3: marrow spaces yes, the cranial cavity no).
  double maxHoleVolumeMm3 = 20000.0;
  /// Holes whose mean HU is below this stay empty (air cells), HU.
  float holeMinMeanHU = -200.0f;
  /// Estimate the bone fraction of surface voxels from their HU (else 1 inside the mask, 0
  /// outside).
  bool partialVolume = true;
};

using FractionImage = itk::Image<float, 3>;

struct BoneSegmentation {
  FractionImage::Pointer fraction; ///< bone fraction per CT voxel, 0..1
  HUImage::Pointer boneHU;         ///< HU of the bone material where fraction > 0 (NaN elsewhere)
  double boneVolumeMm3 = 0;        ///< sum of fractions x voxel volume, mm^3
  Box3 boneBounds;                 ///< world box (mm) around the voxels with fraction > 0
  int64_t thresholdVoxels = 0;     ///< voxels >= threshold (all components)
  int64_t keptVoxels = 0;          ///< voxels of the kept component(s), before hole filling
  int64_t filledVoxels = 0;        ///< voxels added by hole filling
  int numComponents = 0;           ///< components above the threshold
  int holesFilled = 0;             ///< number of holes filled
};

/// Segment the bone of `ct` (HU). Throws std::runtime_error when no voxel reaches the threshold,
/// when the seed lies outside the image or is not on bone. Progress stage "segmenting bone".
BoneSegmentation SegmentBone(const CTImage& ct, const SegmentationOptions& options = {},
                             const Progress& progress = {});

/// The part of `ct` inside the world box `roiMm` (mm), grown by marginVoxels voxels on each side
/// and clamped to the image. Throws std::runtime_error when the box misses the image.
CTImage CropCT(const CTImage& ct, const Box3& roiMm, int marginVoxels = 2);

} // namespace bm
