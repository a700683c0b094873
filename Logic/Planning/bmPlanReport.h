// bmPlanReport.h - the pre-operative plan report (Markdown, HTML and JSON): the landmarks and where
// each came from, the measurements with their methods, the planned axis and its correction, the
// reamer check, the steps and the warnings; with a phantom, its truth beside each value. When no
// glenoid was found the report says so and lists the landmarks to place.
#pragma once

#include "bmGlenoidPlan.h"

#include <nlohmann/json.hpp>

#include <string>

namespace bm {

struct PlanReportInput {
  std::string source;                          ///< the CT (path or "phantom: ...")
  std::string importSummary;                   ///< what was read and segmented (several lines)
  const GlenoidLandmarks* landmarks = nullptr; ///< null: no glenoid found
  const GlenoidMeasurements* measurements = nullptr;
  const GlenoidPlan* plan = nullptr;
  std::string failure;  ///< why no plan (NoGlenoidFound's message) when landmarks is null
  /// The failure's picture beside the report (a file name: bmFailurePicture.h), "" for none.
  std::string failurePicture;
  nlohmann::json truth; ///< a phantom's ScapulaTruthJson, or null
};

/// JSON: {"status": "planned" | "no_glenoid", "source", "message"?, "landmarks",
/// "measurements", "plan", "truth"?, "landmarks_to_place"?}.
nlohmann::json PlanReportJson(const PlanReportInput& in);
/// The same as a Markdown document for the surgeon.
std::string PlanReportMarkdown(const PlanReportInput& in);
/// The same as an HTML page (no scripts; the failure's picture, when there is one, is the file
/// beside it).
std::string PlanReportHtml(const PlanReportInput& in);

} // namespace bm
