// bmDicomSegmentation.h - the bone before and after a plan's steps as a DICOM Segmentation (SEG,
// binary) on the source CT's patient, study and frame of reference, so that a PACS viewer shows
// the reamed bone over the images it came from (DCMTK dcmseg).
//
// Segments: 1 "Bone removed" (voxels at least half bone before and less than half after), 2 "Bone
// remaining" (at least half bone after). Frames: the voxmap's z slices (world-aligned, LPS),
// rows along y and columns along x at the voxel spacing, one frame per segment and slice that
// holds any of its voxels; each frame references the source image nearest its z (Derivation
// Image). Units: mm.
#pragma once

#include <string>

#include "bmDicomSource.h"
#include "bmVoxmap.h"

namespace bm {

struct DicomSegmentationInfo {
  std::string seriesDescription = "BoneMachining reaming";
  int seriesNumber = 9001;
  std::string softwareVersion; ///< e.g. bmsim's version
};

/// What was written: frames per segment and the SEG's own UIDs.
struct DicomSegmentationResult {
  int removedFrames = 0, remainingFrames = 0;
  std::string sopInstanceUID, seriesUID;
};

/// Writes `path` (atomically: a temporary beside it renamed into place) from the voxmaps before
/// and after (same grid; each at most 65535 cells across). Throws std::invalid_argument for
/// grids that differ or are too large, std::runtime_error naming DCMTK's error otherwise.
DicomSegmentationResult WriteReamingSegmentation(const std::string& path, const DicomSource& source,
                                                 const Voxmap& before, const Voxmap& after,
                                                 const DicomSegmentationInfo& info = {});

} // namespace bm
