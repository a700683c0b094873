// bmsimRunSteps.h - `bmsim run PLAN.json` for a scene with steps (bmScene.h SceneStep), e.g. the
// glenoid plan that `bmsim plan` writes: the guide-pin hole, then the nipple-guided reaming, each
// a scripted feed on the bone the step before left.
//
// Outputs in DIR: one folder per step, "<k>-<name>" (forces.csv, summary.json and, unless
// --no-report, the step's report and cut surface), then DIR/summary.json: the plan, each step's
// figures and warnings, and the outcome on the bone (bmReamingOutcome.h) when the scene carries a
// plan. The step folders and the summary appear together (a failed step leaves nothing).
#pragma once

#include <string>

#include "bmScene.h"
#include "bmsimArgs.h"

namespace bm::cli {

/// Runs every step of `scene` in order on one bone; returns the exit code (0; 1 when a step's guide
/// met solid bone, so a script can tell that the plan did not complete).
int RunSceneSteps(const bm::Scene& scene, const ParsedArgs& args, const std::string& outDir);

} // namespace bm::cli
