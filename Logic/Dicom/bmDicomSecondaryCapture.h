// bmDicomSecondaryCapture.h - a report's picture (a PNG the report wrote) as a DICOM Secondary
// Capture image beside the CT: the source series' patient and study, a series of its own, RGB
// pixels as the picture has them, so that a PACS viewer shows the plan's pictures next to the
// CT (Docs/Dicom.md).
#pragma once

#include <string>

#include "bmDicomSource.h"

namespace bm {

struct DicomPictureInfo {
  std::string seriesUID; ///< the pictures' series ("" = a new one)
  int seriesNumber = 9003;
  int instanceNumber = 1;
  std::string description;     ///< what the picture shows (Image Comments, Derivation)
  std::string softwareVersion; ///< e.g. bmsim's version
};

/// Writes `png` (8-bit RGB, RGBA or grey; converted to RGB) as a Secondary Capture image at `path`
/// (atomically). Returns the SOP Instance UID. Throws std::runtime_error naming the file when the
/// picture cannot be read (not a PNG, larger than 16384 pixels a side) or DCMTK fails.
std::string WriteSecondaryCapture(const std::string& path, const DicomSource& source,
                                  const std::string& png, const DicomPictureInfo& info);

} // namespace bm
