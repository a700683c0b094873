// bmPlanResult.h - the result of a plan's steps run on one bone, as both faces write it: bmsim run
// on a plan scene (its scripted steps, bmsimRunSteps.h) and the viewer's Write plan result (the
// sessions a surgeon ran, vtkBMGlenoidPlanFilter::WriteResult). The summary (the plan, each step's
// figures, the outcome on the bone: bmReamingOutcome.h, with the reamed face's angles in the
// plan's frame: bmPlanRunReport.h WithFaceAngles), the glenoid's pictures before and after with
// the plan drawn (given by the caller: bmGlenoidPictures.h draws them where VTK rendering is
// built) and the report (plan_result.md / .html).
#pragma once

#include "bmVec3.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <utility>

namespace bm {

class ToolModel;
class Voxmap;

struct PlanResultInput {
  std::string planName;                           ///< the plan scene's name
  nlohmann::json planning;                        ///< the plan scene's "planning" (null: none)
  nlohmann::json steps = nlohmann::json::array(); ///< per step: {step, name, description,
                                                  ///< folder, tool, summary}
  bool completed = true;          ///< every step reached its depth (no guide blocked)
  const Voxmap* before = nullptr; ///< the bone before the first step (required)
  const Voxmap* after = nullptr;  ///< the bone after the last (required; same grid)
  /// The reaming step's reamer and reached depth (mm): with them the outcome is measured along
  /// the plan's entry and axis (or `trialEntry` / `trialAxis` when the plan has none).
  const ToolModel* reamer = nullptr;
  double reamReachedMm = 0;
  Vec3 trialEntry{}, trialAxis{0, 0, 1};
};

/// Draws the glenoid before and after into a folder with the plan drawn; returns the two file
/// names (bmGlenoidPictures.h WriteGlenoidPictures).
using PlanPictureWriter = std::function<std::pair<std::string, std::string>(
    const std::string& dir, const Voxmap& before, const Voxmap& after,
    const nlohmann::json& planning)>;

/// The summary: {"plan", "steps", "completed", "planning"?, "outcome"? (with its "options"),
/// "pictures"? (file names, filled by WritePlanResult)} with the reamed face's angles.
/// Throws std::invalid_argument when before or after is missing or their grids differ.
nlohmann::json PlanResultSummary(const PlanResultInput& in);

/// Writes into `dir` (created when missing): the pictures (with `pictures` given and a plan with
/// an entry and axis), then plan_result.md, plan_result.html and summary.json all at once
/// (bmAtomicFile.h; the summary says the set is complete). Returns the summary written. Throws
/// as PlanResultSummary, std::runtime_error when a file cannot be written.
nlohmann::json WritePlanResult(const std::string& dir, const PlanResultInput& in,
                               const PlanPictureWriter& pictures = nullptr);

} // namespace bm
