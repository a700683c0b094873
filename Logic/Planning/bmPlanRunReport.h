// bmPlanRunReport.h - the report of a plan that was run (`bmsim run plan.json`): what the surgeon
// decides on after rehearsing the pin and the reaming. From the plan summary (bmsimRunSteps.h):
// the pre-operative version and inclination, the planned axis, each step's reached depth, removed
// volume, mean thrust and torque and warnings (with a link to its own report: forces over time,
// the cut surface and its picture), and the outcome (bmReamingOutcome.h): removed cortical and
// cancellous bone, the reamed face's orientation against the target as version and inclination in
// the plan's scapular frame, medialisation, baseplate seating, bone beyond the pin and the peg.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace bm {

/// Adds to the summary's "outcome" the reamed face's version and inclination (deg) in the plan's
/// scapular frame ("reamed_face_version_deg", "reamed_face_inclination_deg") and their errors
/// against the plan's targets, when the summary carries both an outcome and a planning block with
/// measurements.scapular_frame. Returns the summary.
nlohmann::json WithFaceAngles(nlohmann::json summary);

/// The report as Markdown and as a self-contained HTML page.
std::string PlanRunMarkdown(const nlohmann::json& summary);
std::string PlanRunHtml(const nlohmann::json& summary);

} // namespace bm
