// bmDicomSeriesWriter.h - write a CT volume as a real DICOM series (one CT Image Storage file per
// slice), so phantoms exercise the whole import path (GDCM parsing, ordering, rescale, decoding).
//
// Each slice: 16-bit unsigned stored values = round(HU) + 1024 (clamped to 0..65535) with
// RescaleIntercept -1024, RescaleSlope 1, RescaleType HU; ImagePositionPatient/
// ImageOrientationPatient from the image's origin and direction, PixelSpacing, SliceThickness =
// slice spacing, one SeriesInstanceUID/StudyInstanceUID/FrameOfReferenceUID for the series and a
// SOPInstanceUID per file (GDCM's UID generator). Files are named IM00001.dcm, IM00002.dcm, ...
//
// Atomic: the series is written into a temporary sibling folder which is renamed to `folder` only
// when every slice is written; `folder` must not exist or be empty.
#pragma once

#include "bmCTImage.h"
#include "bmProgress.h"

#include <string>

namespace bm {

struct DicomWriteOptions {
  std::string modality = "CT";
  std::string seriesUID; ///< "" = generate one
  std::string studyUID;  ///< "" = generate one
  std::string seriesDescription = "BoneMachining";
  std::string patientName = "BoneMachining^Phantom";
  std::string patientID = "BM-PHANTOM";
  /// "" or "explicit" (uncompressed explicit VR little endian), "rle", "jpeg-lossless"
  /// (process 14 SV1), "jpeg-ls" (lossless) or "jpeg2000" (lossless).
  std::string transferSyntax;
};

/// Write ct.hu as a DICOM series into `folder` (see above); returns the SeriesInstanceUID.
/// Throws std::runtime_error when the folder exists and is not empty, or a slice cannot be written.
std::string WriteDicomSeries(const CTImage& ct, const std::string& folder,
                             const DicomWriteOptions& options = {}, const Progress& progress = {});

} // namespace bm
