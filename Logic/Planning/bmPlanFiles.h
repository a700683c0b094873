// bmPlanFiles.h - a plan's files in a folder, as both faces write them (bmsim plan; the viewer's
// Write plan report): the plan scene and its two step scenes, and the pre-operative report.
#pragma once

#include "bmGlenoidPlan.h"
#include "bmPlanReport.h"

#include <string>

namespace bm {

/// Writes into `dir` (created when missing; files there of the same names are replaced) all at
/// once (bmAtomicFile.h WriteFilesAtomic: all or none): with `scenes`, plan.json (both steps),
/// step1-guide-pin.json and step2-ream.json (single-step scenes for bmsim run); always
/// plan_report.md, .html and .json (a failed plan's report says why). Returns the names written,
/// relative to `dir`. Throws std::runtime_error when a file cannot be written.
std::vector<std::string> WritePlanFiles(const std::string& dir, const PlanReportInput& report,
                                        const PlanScenes* scenes);

} // namespace bm
