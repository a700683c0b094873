// bmCTReader.h - read a CT in Hounsfield units from a DICOM folder or a single volume file.
//
// Inputs:
//  - a folder of DICOM files (one level, not recursive): every file's header is read with GDCM,
//  files
//    are grouped by SeriesInstanceUID, the chosen series' slices are ordered by their position
//    along the slice normal (ImagePositionPatient projected on ImageOrientationPatient's normal),
//    checked (same size, orientation and pixel spacing; uniform slice spacing), then each slice's
//    pixels are read through ITK's GDCMImageIO, which decodes the compressed transfer syntaxes GDCM
//    supports (RLE, JPEG lossless/lossy, JPEG-LS, JPEG 2000) and applies RescaleSlope/Intercept ->
//    HU;
//  - a single volume: .nrrd/.nhdr, .mha/.mhd, .nii/.nii.gz (values taken as HU);
//  - an InVesalius project (.inv3: a tar.gz holding main.plist and the raw matrix), which is how
//    Debian's invesalius-examples ships its head CT.
//
// Refused with std::runtime_error naming the problem (nothing is allocated for the voxels before
// the size was checked against ReadOptions::maxMemoryBytes): an empty folder, a folder without a
// readable DICOM series, several series without ReadOptions::seriesUID (the message lists them),
// unreadable/truncated/corrupt DICOM files, a non-CT modality (unless allowNonCT), missing or zero
// pixel spacing, missing slice positions, a single slice, duplicate or non-uniform slice spacing
// (a missing slice), multi-frame files, and a volume larger than the memory allowed.
#pragma once

#include "bmCTImage.h"
#include "bmProgress.h"

#include <cstdint>
#include <string>
#include <vector>

namespace bm {

struct ReadOptions {
  /// SeriesInstanceUID to read when a DICOM folder holds several series ("" = the only one).
  std::string seriesUID;
  /// Largest CT (bytes of float HU voxels) the reader may allocate; 0 = DefaultMemoryLimit().
  uint64_t maxMemoryBytes = 0;
  /// Accept modalities other than CT (values are then not HU; segmentation thresholds will be off).
  bool allowNonCT = false;
  /// Largest accepted deviation of a slice gap from the mean gap, mm, and relative to the mean
  /// gap; a gap off by more than both is refused as inconsistent slice spacing (a missing slice).
  double sliceGapToleranceMm = 0.01;
  double sliceGapToleranceRel = 0.01;
};

/// One DICOM series found in a folder.
struct DicomSeriesInfo {
  std::string uid;         ///< SeriesInstanceUID
  std::string modality;    ///< e.g. "CT", "MR"
  std::string description; ///< SeriesDescription
  int numFiles = 0;
};

/// Default memory budget: 75 % of the machine's physical memory, in bytes.
uint64_t DefaultMemoryLimit();

/// The DICOM image series in a folder (files without pixel data are left out). Throws
/// std::runtime_error when the folder is missing, empty, or holds files GDCM cannot parse.
std::vector<DicomSeriesInfo> ListDicomSeries(const std::string& folder);

/// Read a CT (folder or file, see above). Progress: "reading DICOM" / "reading volume".
CTImage ReadCT(const std::string& path, const ReadOptions& options = {},
               const Progress& progress = {});

} // namespace bm

namespace bm {
/// Throw std::runtime_error "<what> needs N MiB ..., more than the M MiB allowed" when bytes
/// exceeds limitBytes (0 = DefaultMemoryLimit()). Called before any large allocation.
void CheckMemoryBudget(uint64_t bytes, uint64_t limitBytes, const std::string& what);
/// Set ct.huMin/huMax from the voxels; adds a warning when the range does not look like HU.
void UpdateHURange(CTImage& ct);
} // namespace bm
