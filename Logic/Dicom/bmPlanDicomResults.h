// bmPlanDicomResults.h - a plan run's results as DICOM beside its CT: the bone before and after
// the steps as a Segmentation (bmDicomSegmentation.h) and the plan's measurements and outcome as
// a Structured Report (bmDicomMeasurementReport.h), both in the source series' patient, study and
// frame of reference, and the result's pictures as Secondary Captures (bmDicomSecondaryCapture.h)
// in the same study. One place builds them for every face (bmsim run --dicom, the viewer's Write
// result; Docs/Dicom.md).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bmDicomMeasurementReport.h"
#include "bmVoxmap.h"

namespace bm {

/// The measurements of a plan result's summary (bmPlanResult.h: "planning" with its
/// "measurements", and "outcome"), each with its unit and method; those the summary lacks (or
/// holds as null) are left out.
std::vector<DicomMeasurement> PlanMeasurements(const nlohmann::json& summary);

struct PlanDicomFiles {
  std::string segmentation, report;  ///< paths written
  std::vector<std::string> pictures; ///< the Secondary Captures written (none without pictures)
};

/// Writes DIR/reamed-bone.seg.dcm and DIR/plan.sr.dcm (DIR created when missing) for the CT
/// series in `dicomFolder` (seriesUID "" = its only series), and, when the summary names pictures
/// ("pictures": {"before": PNG, "after": PNG}, files in `pictureDir`), DIR/glenoid_before.sc.dcm
/// and DIR/glenoid_after.sc.dcm in one series. Throws std::runtime_error naming the problem (the
/// folder is not a DICOM series, the summary has no measurement, a picture cannot be read,
/// DCMTK's error).
PlanDicomFiles WritePlanDicomResults(const std::string& dir, const std::string& dicomFolder,
                                     const std::string& seriesUID, const Voxmap& before,
                                     const Voxmap& after, const nlohmann::json& summary,
                                     const std::string& softwareVersion,
                                     const std::string& pictureDir = "");

} // namespace bm
