// bmDicomMeasurementReport.h - a plan's measurements and outcome as a DICOM Structured Report
// (Comprehensive SR in the shape of TID 1500, "Imaging Measurement Report"), in the source CT's
// patient and study, so that a PACS keeps them beside the images (DCMTK dcmsr).
//
// Tree: CONTAINER Imaging Measurement Report (126000, DCM) with the language (en-US) and the
// observer (a device: BoneMachining); CONTAINER Image Library (111028, DCM) > Image Library Group
// (126200, DCM) > an IMAGE item per source image; CONTAINER Imaging Measurements (126010, DCM) >
// Measurement Group (125007, DCM) with its tracking identifier (112039) and UID (112040), then per
// measurement a NUM (its concept in the private scheme 99BMSIM, its value and UCUM unit) with
// its method as TEXT (370129005, SCT, "Measurement Method") and INFERRED FROM the image library.
// There are no standard codes for glenoid version, inclination or seating; the private concepts
// name them in full.
#pragma once

#include <string>
#include <vector>

#include "bmDicomSource.h"

namespace bm {

struct DicomMeasurement {
  std::string code;   ///< private code value (99BMSIM), e.g. "version-3d"; at most 16 characters
  std::string name;   ///< code meaning, at most 64 characters, e.g. "Glenoid version (3D)"
  double value = 0;   ///< in `unit`
  std::string unit;   ///< UCUM: "deg", "mm", "mm3", "%"
  std::string method; ///< how it was measured, in words
};

struct DicomReportInfo {
  std::string title = "Glenoid plan and reaming outcome"; ///< the measurement group's tracking id
  std::string seriesDescription = "BoneMachining plan";
  int seriesNumber = 9002;
  std::string softwareVersion;
};

/// Writes `path` (atomically) and returns the report's SOPInstanceUID. Throws
/// std::invalid_argument for an empty list, a code longer than 16 characters, a name longer than
/// 64 or a value that is not finite; std::runtime_error naming DCMTK's error otherwise.
std::string WriteMeasurementReport(const std::string& path, const DicomSource& source,
                                   const std::vector<DicomMeasurement>& measurements,
                                   const DicomReportInfo& info = {});

} // namespace bm
