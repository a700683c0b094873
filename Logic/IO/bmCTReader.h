// bmCTReader.h - read a CT in Hounsfield units from a DICOM folder or a single volume file.
//
// Inputs:
//  - a folder of DICOM files (one level, not recursive): every file's header is read with GDCM,
//    files are grouped into series by SeriesInstanceUID, or when that is empty or missing by
//    SeriesNumber, ImageOrientationPatient, Rows/Columns, StudyInstanceUID and Modality (the series
//    then gets an id "noUID-<number>-<modality>-<cols>x<rows>-<hash>" and a note says how it was
//    grouped); the chosen series' slices are ordered by their position
//    along the slice normal (ImagePositionPatient projected on ImageOrientationPatient's normal),
//    checked (same size, orientation and pixel spacing; uniform slice spacing), then each slice's
//    pixels are read through ITK's GDCMImageIO, which decodes the compressed transfer syntaxes GDCM
//    supports (RLE, JPEG lossless/lossy, JPEG-LS, JPEG 2000) and applies RescaleSlope/Intercept ->
//    HU;
//  - a single DICOM file (any name; recognised by its "DICM" magic at byte 128 or a .dcm
//    extension): the series it belongs to in its folder is read (a note says so); multi-frame
//    files are refused;
//  - a single volume: .nrrd/.nhdr, .mha/.mhd, .nii/.nii.gz, its header checked first
//    (bmHeaderCheck.h: sizes, spacing, origin, direction, data file place, truncation);
//  - an InVesalius project (.inv3: a tar.gz holding main.plist and the raw matrix), which is how
//    Debian's invesalius-examples ships its head CT.
//
// Refused with std::runtime_error naming the problem (nothing is allocated for the voxels before
// the size was checked against ReadOptions::maxMemoryBytes): an empty folder, a folder without a
// readable DICOM series, several series without ReadOptions::seriesUID (the message lists them),
// unreadable/truncated/corrupt DICOM files, a non-CT modality (unless allowNonCT), missing or zero
// pixel spacing, missing slice positions, a single slice, duplicate or non-uniform slice spacing
// (a missing slice), slices with a modality, orientation or pixel spacing unlike the others,
// non-finite ImagePositionPatient/ImageOrientationPatient or rescale slope/intercept, multi-frame
// files, inputs that are not regular files, and a volume larger than the memory allowed. ITK and
// GDCM exceptions become std::runtime_error naming the file.
//
// Values: after reading, bmIntensityMapping.h decides whether they are HU (refusing clearly
// non-HU data unless ReadOptions::intensity says how to read it); a given HU mapping is applied to
// the voxels here. CTImage::intensity records the decision.
#pragma once

#include "bmCTImage.h"
#include "bmIntensityMapping.h"
#include "bmMemoryBudget.h" // DefaultMemoryLimit, CheckMemoryBudget
#include "bmProgress.h"

#include <cstdint>
#include <string>
#include <vector>

namespace bm {

struct ReadOptions {
  /// Series to read when a DICOM folder holds several: its id as ListDicomSeries gives it (the
  /// SeriesInstanceUID, or the "noUID-..." id of a series without one); "" = the only one.
  std::string seriesUID;
  /// Largest CT (bytes of float HU voxels) the reader may allocate; 0 = DefaultMemoryLimit().
  uint64_t maxMemoryBytes = 0;
  /// Bytes per CT voxel the caller needs beside the voxel's own 4 (bmImport's segmentation of a
  /// whole CT: 18), counted against maxMemoryBytes with them when the size is first known (from
  /// a header), so that a CT too large to import is refused before it is read. Default 0.
  uint64_t extraBytesPerVoxel = 0;
  /// Accept modalities other than CT (values are then not HU; segmentation thresholds will be off).
  bool allowNonCT = false;
  /// Largest accepted deviation of a slice gap from the mean gap, mm, and relative to the mean
  /// gap; a gap off by more than both is refused as inconsistent slice spacing (a missing slice).
  double sliceGapToleranceMm = 0.01;
  double sliceGapToleranceRel = 0.01;
  /// How to read values that are not HU (default: decide from the file; see bmIntensityMapping.h).
  IntensityOptions intensity;
  /// Accept a detached data file (NRRD "data file", MetaImage ElementDataFile) given by an
  /// absolute path, with "..", or leading outside the header's folder. Default false.
  bool allowDataOutsideFolder = false;
};

/// One DICOM series found in a folder.
struct DicomSeriesInfo {
  std::string uid;          ///< the series' id: SeriesInstanceUID, or "noUID-..." without one
  std::string modality;     ///< e.g. "CT", "MR"
  std::string description;  ///< SeriesDescription
  int numFiles = 0;         ///< slices (image files)
  int rows = 0, cols = 0;   ///< slice size, pixels
  std::string seriesNumber; ///< SeriesNumber (0020,0011), "" when absent
  bool hasUID = true;       ///< false: grouped by other attributes (see above)
};

/// The DICOM image series in a folder (files without pixel data are left out). Throws
/// std::runtime_error when the folder is missing, empty, or holds files GDCM cannot parse.
std::vector<DicomSeriesInfo> ListDicomSeries(const std::string& folder);

/// Read a CT (folder or file, see above). Progress: "reading DICOM" / "reading volume".
CTImage ReadCT(const std::string& path, const ReadOptions& options = {},
               const Progress& progress = {});

} // namespace bm

namespace bm {
/// Set ct.huMin/huMax from the voxels (remarks on the range come from DecideIntensity).
void UpdateHURange(CTImage& ct);

/// What the values of `ct` (as read: the file's own rescale applied) mean: completes `evidence`
/// with the value range, decides the mapping (bmIntensityMapping.h DecideIntensity) into
/// ct.intensity, turns the values into HU when the user gave a mapping, and updates the HU range.
/// Throws std::runtime_error on a non-finite value (naming evidence.file) and when DecideIntensity
/// refuses the values.
void ApplyIntensityDecision(CTImage& ct, IntensityEvidence evidence, const IntensityOptions& options);
} // namespace bm
