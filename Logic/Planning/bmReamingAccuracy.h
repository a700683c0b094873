// bmReamingAccuracy.h - what a reaming scene's result is worth at a resolution: the scene's
// offline trial (bmFeedTrial.h: the reamer fed along the trial axis to the scene's depth, one
// engine frame per period) on the bone at that resolution, its outcome measured
// (bmReamingOutcome.h: removed volume, the reamed face's depth and orientation, the baseplate's
// seating), and the outcome compared with the same trial at a finer, converged resolution. The
// cut's geometry comes from the tool, which is known exactly; the voxmap's resolution is what
// blurs it, so this is what a session's resolution costs in accuracy (bmsim bench --session
// --accuracy, the session's speed-against-accuracy chart; Docs/RealTime.md).
#pragma once

#include "bmReamingOutcome.h"
#include "bmScene.h"
#include "bmVoxmap.h"

namespace bm {

/// One resolution's trial and its outcome.
struct ReamingTrialOutcome {
  int voxmap = 0, shell = 0; ///< the scene's resolutions the trial ran at
  double voxelMm = 0;        ///< the bone's voxel edge, mm
  ReamingOutcome outcome;
  double seconds = 0; ///< wall-clock time of the trial, s
};

/// Runs `scene`'s offline trial on `bone` (the scene's bone at scene.voxmapResolution: the caller
/// builds it, e.g. with MakeSceneBone) and measures the outcome at the trial's entry and axis
/// with `options` (the baseplate, and the bone's guide-pin hole: its radius and depth, so that the
/// face's fit leaves it out). Throws std::invalid_argument when the scene's tool is not a reamer
/// or the scene has plan steps (one trial, one tool).
ReamingTrialOutcome RunReamingTrial(const Scene& scene, Voxmap bone,
                                    const ReamingOutcomeOptions& options);

/// The outcome options for the glenoid phantom's bone (the CT phantom or its analytic twin): the
/// default baseplate with the phantom's guide-pin hole (radius and depth, bmAnalyticGlenoid.h),
/// so that the face's fit leaves the hole out.
ReamingOutcomeOptions GlenoidPhantomOutcomeOptions();

/// A resolution's outcome against the converged reference's.
struct ReamingAccuracy {
  double removedErrorPct = 0; ///< (removed - reference) / reference, %
  double depthErrorMm = 0;    ///< reamed face's depth (medialisation) minus the reference's, mm
  double faceErrorDeg = 0;    ///< angle between the two fitted face normals, deg (>= 0)
  double seatingErrorPct = 0; ///< seating minus the reference's, percentage points
  double reachedErrorMm = 0;  ///< reached depth minus the reference's, mm
};

/// Compares `cell` with `reference` (signed where the sign says something, see the fields).
/// Throws std::invalid_argument when the reference removed no bone.
ReamingAccuracy CompareReamingOutcomes(const ReamingOutcome& cell, const ReamingOutcome& reference);

} // namespace bm
