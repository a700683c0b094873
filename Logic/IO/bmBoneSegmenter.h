// bmBoneSegmenter.h - bone from a CT in Hounsfield units, with ITK filters: the segment stage of
// the CT chain read -> intensity -> segment -> separate -> fill -> resample (Docs/Segmentation.md).
//
// Steps (each reported through Progress):
//  1. threshold: voxels with HU >= thresholdHU are bone (default 200 HU: above soft tissue and
//     marrow, below cancellous bone of ordinary density; InVesalius' bone preset is 226 HU);
//     (with an oriented box, bone outside it is dropped: bmBoxROI.h);
//  2. components (26-connected, bmMask.h LabelComponents): keep the component holding the seed
//     point, else the largest, else (keepAllComponents) all;
//  3. separate (bmBoneSeparation.h): when an exclude seed lies on the kept component, the bones
//     joined across a joint space are split and only the include seed's bone is kept;
//  4. fill cavities (bmCavityFill.h): closing, cavities inside the bone and cavities cut open by
//     the image border, up to maxHoleVolumeMm3, mean HU at least holeMinMeanHU;
//  5. partial volume: bone fraction per voxel. Voxels away from the bone surface are 1 (bone) or 0;
//     a voxel within one voxel of the surface gets (HU - soft) / (bone - soft) clamped to [0, 1],
//     with soft = mean HU of the pure non-bone voxels and bone = the highest HU of the pure bone
//     voxels within 2 voxels (so a voxel half filled with cortical bone counts half, not all, as a
//     threshold would make it). Filled-cavity voxels are 1.
//
// The HU of the bone at each bone voxel (boneHU) is kept for the material scale: inside the bone
// its own HU, at the surface the bone reference above (its own HU is diluted by the soft tissue).
#pragma once

#include "bmExcludedHead.h"

#include "bmBoneSeparation.h"
#include "bmBoxROI.h"
#include "bmCTImage.h"
#include "bmCavityFill.h"
#include "bmProgress.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bm {

struct SegmentationOptions {
  /// Bone threshold, HU (voxels at or above are bone).
  float thresholdHU = 200.0f;
  /// The values' unit in messages: "HU", or "(the file's units)" when the values are used as
  /// stored (bmIntensityMapping.h AdjustForIntensity).
  std::string valueUnit = "HU";
  /// World point (mm): keep the connected component containing it (or touching it within one
  /// voxel). Without a seed the largest component is kept.
  std::optional<std::array<double, 3>> seedMm;
  /// Oriented box region of interest (bmBoxROI.h): bone voxels whose centres lie outside it are
  /// dropped after the threshold. Default none.
  std::optional<OrientedBox> box;
  /// World points (mm) on bones to drop: bones joined to the kept one are separated from it
  /// (bmBoneSeparation.h). A point off all bone is reported in the warnings and ignored.
  std::vector<std::array<double, 3>> excludeSeedsMm;
  /// Humeral heads whose bone is left out after the threshold (bmExcludedHead.h): a head a plan
  /// cut off its glenoid (bmJoinedHeadCut.h), so that a step's bone keeps none of it in front of
  /// the face. Default none.
  std::vector<ExcludedHead> excludeHeads;
  /// Keep every component above the threshold (ignored when a seed is given).
  bool keepAllComponents = false;
  /// Separation of touching bones (used when an exclude seed lies on the kept bone).
  SeparationOptions separation;
  /// Fill cavities (bmCavityFill.h; on by default).
  bool fillHoles = true;
  /// Closing before the cavity fill, ball radius in voxels (0 = none). Default 1.
  int closingRadiusVoxels = 1;
  /// Largest hole filled, mm^3 (default 20 cm^3: marrow spaces yes, the cranial cavity no).
  double maxHoleVolumeMm3 = 20000.0;
  /// Holes whose mean HU is below this stay empty (air cells), HU.
  float holeMinMeanHU = -200.0f;
  /// Estimate the bone fraction of surface voxels from their HU (else 1 inside the mask, 0
  /// outside).
  bool partialVolume = true;
  /// Metal (implants, screws): voxels at or above this, HU, are not bone, are not filled back
  /// as a cavity, and are named in the warnings with their volume and place. Default 2500 HU
  /// (cortical bone stays below about 2000 HU; titanium and steel reach 3000 and saturate the
  /// scanner's range). Raw values (not HU): off (+infinity); off too when the bone threshold is
  /// at or above it.
  float metalHU = 2500.0f;
};

using FractionImage = itk::Image<float, 3>;

struct BoneSegmentation {
  FractionImage::Pointer fraction;   ///< bone fraction per CT voxel, 0..1
  HUImage::Pointer boneHU;           ///< HU of the bone material where fraction > 0 (NaN elsewhere)
  double boneVolumeMm3 = 0;          ///< sum of fractions x voxel volume, mm^3
  Box3 boneBounds;                   ///< world box (mm) around the voxels with fraction > 0
  int64_t thresholdVoxels = 0;       ///< voxels >= threshold (all components)
  int64_t keptVoxels = 0;            ///< voxels of the kept component(s), before hole filling
  int64_t filledVoxels = 0;          ///< voxels added by hole filling
  int64_t metalVoxels = 0;           ///< voxels at or above the metal threshold, left out
  int64_t headVoxels = 0;            ///< bone voxels of the excluded heads, left out
  int numComponents = 0;             ///< components above the threshold
  int holesFilled = 0;               ///< number of cavities filled
  int borderHolesFilled = 0;         ///< of which cut open by the image border
  SeparationResult separation;       ///< depthMm > 0 when touching bones were split
  std::vector<std::string> warnings; ///< seeds off the bone, ...
};

/// Segment the bone of `ct` (HU). Throws std::runtime_error when no voxel reaches the threshold,
/// when the (include) seed lies outside the image or is not on bone, or when the bones at the
/// include and exclude seeds cannot be separated. Progress stage "segmenting bone".
BoneSegmentation SegmentBone(const CTImage& ct, const SegmentationOptions& options = {},
                             const Progress& progress = {});

/// The part of `ct` inside the world box `roiMm` (mm), grown by marginVoxels voxels on each side
/// and clamped to the image. Throws std::runtime_error when the box misses the image.
CTImage CropCT(const CTImage& ct, const Box3& roiMm, int marginVoxels = 2);

} // namespace bm
