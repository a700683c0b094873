// bmReamingAccuracy.cxx - see bmReamingAccuracy.h.
#include "bmReamingAccuracy.h"

#include <chrono>
#include <stdexcept>

#include "bmAnalyticGlenoid.h"
#include "bmFeedTrial.h"
#include "bmMachiningSetup.h"
#include "bmVec3.h"

namespace bm {

ReamingOutcomeOptions GlenoidPhantomOutcomeOptions() {
  ReamingOutcomeOptions o;
  o.pinRadiusMm = glenoid::kRp;
  o.pinDepthMm = glenoid::kDp;
  return o;
}

ReamingTrialOutcome RunReamingTrial(const Scene& scene, Voxmap bone,
                                    const ReamingOutcomeOptions& options) {
  if (!scene.steps.empty())
    throw std::invalid_argument("reaming accuracy: scene '" + scene.name +
                                "' is a plan of steps; give one of its steps");
  const auto start = std::chrono::steady_clock::now();
  const Voxmap before = bone;
  MachiningSetup setup(scene, std::move(bone));
  if (!dynamic_cast<const ArcLipTool*>(&setup.Tool()))
    throw std::invalid_argument("reaming accuracy: scene '" + scene.name + "' cuts with a " +
                                setup.Tool().Kind() + ", not a reamer");
  FeedTrial trial(setup);
  trial.Run();
  const nlohmann::json summary = trial.Summary();
  const Vec3 entry{scene.trial.entry.x(), scene.trial.entry.y(), scene.trial.entry.z()};
  const Vec3 axis = Normalized({scene.trial.axis.x(), scene.trial.axis.y(), scene.trial.axis.z()});
  ReamingTrialOutcome r;
  r.voxmap = scene.voxmapResolution;
  r.shell = scene.shellResolution;
  r.voxelMm = before.Spacing();
  r.outcome = MeasureReamingOutcome(before, setup.Bone(), entry, axis, setup.Tool(),
                                    summary.at("reached_depth_mm").get<double>(), options);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

ReamingAccuracy CompareReamingOutcomes(const ReamingOutcome& cell,
                                       const ReamingOutcome& reference) {
  if (!(reference.removedMm3 > 0))
    throw std::invalid_argument("reaming accuracy: the reference trial removed no bone");
  ReamingAccuracy a;
  a.removedErrorPct = 100.0 * (cell.removedMm3 - reference.removedMm3) / reference.removedMm3;
  a.depthErrorMm = cell.faceDepthMm - reference.faceDepthMm;
  a.faceErrorDeg = AngleDeg(cell.faceNormal, reference.faceNormal);
  a.seatingErrorPct = 100.0 * (cell.seating - reference.seating);
  a.reachedErrorMm = cell.reachedDepthMm - reference.reachedDepthMm;
  return a;
}

} // namespace bm
