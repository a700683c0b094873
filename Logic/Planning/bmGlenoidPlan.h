// bmGlenoidPlan.h - the glenoid reaming plan (Docs/Planning.md, "The plan"): the corrected
// reaming axis through the glenoid centre at the target version and inclination, a check of the
// reamer's size against the glenoid, and the two steps on one bone as a scene: the guide-pin
// hole drilled along the axis, then the nipple-guided reamer to a set depth. World mm (LPS).
//
// The plan is made from what is available: without the scapular frame (the trigonum or the
// inferior angle not available, bmGlenoidMeasurements.h) the axis is the face normal as found or
// placed (no correction, a warning says why); without the rim the reamer's size is not checked.
// Results a surgeon would not expect (version or inclination beyond +-30 deg, a correction
// beyond 15 deg) are flagged in `implausible` (and among the warnings) before any step runs.
#pragma once

#include "bmGlenoidMeasurements.h"
#include "bmSegmentedBone.h"

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace bm {

struct PlanOptions {
  double targetVersionDeg = 0.0;     ///< deg, within (-45, 45)
  double targetInclinationDeg = 0.0; ///< deg, within (-45, 45)
  /// Reamer diameter, mm (default: the built-in reamer's 36.5 mm, bmToolModel.h ArcLipParams).
  double reamerDiameterMm = 36.5;
  double reamDepthMm = 2.0; ///< reaming depth below the glenoid centre along the axis, mm (> 0)
  double pinRadiusMm = 3.2; ///< guide-pin hole radius, mm (> the reamer nipple's 3 mm)
  double pinDepthMm = 0.0;  ///< mm below the centre; 0 = reamDepth + nipple length (6) + 2 mm
  double pinFeedMmPerRev = 0.05, pinSpeedRpm = 1000; ///< drilling the guide hole
  double reamFeedMmPerRev = 0.1, reamSpeedRpm = 500; ///< reaming
  int voxmapResolution = 192; ///< the scene bone's cells along its region's longest side
  int shellResolution = 340;  ///< the tools' point-shell cells
  double roiHalfMm = 25.0;    ///< the scene bone: a box of +- this around the glenoid centre, mm
  /// Throws std::invalid_argument naming an option out of range.
  void Validate() const;
};

struct GlenoidPlan {
  PlanOptions options;
  Vec3 entry{};                  ///< glenoid centre, world mm
  Vec3 axis{};                   ///< reaming axis, unit, out of the bone (tools feed along -axis)
  double correctionDeg = 0;      ///< angle between the face normal and the axis
  double axisVersionDeg = 0;     ///< the axis' 3D version (= the target)
  double axisInclinationDeg = 0; ///< the axis' inclination (= the target)
  double pinDepthMm = 0;         ///< resolved guide-pin depth, mm
  double clearanceMm = 0;        ///< tool start above the centre: clears the rim, mm
  double reamerOverhangApMm = 0; ///< per side beyond the glenoid's width (0 = within), mm
  double reamerOverhangSiMm = 0; ///< per side beyond its height, mm
  bool reamerFits = false;       ///< no overhang (false when it could not be checked)
  bool corrected = false;        ///< the axis follows the targets in the scapular frame
  std::vector<std::string> warnings;
  /// Measured or planned values outside what glenoids show (each also a warning): check the
  /// landmarks before running the steps.
  std::vector<std::string> implausible;

  /// The plan as a scene with steps (bone = `bone`, a scene bone object):
  /// {"name", "description", "bone", "steps": [{"name": "guide pin", "description", "tool",
  ///  "trial"}, {"name": "ream", ...}], "voxmap_resolution", "shell_resolution", "method",
  ///  "planning": {...}} (bmScene.h's SceneStep layout).
  nlohmann::json SceneJson(const nlohmann::json& bone) const;
  /// Step `i` (0: guide pin, 1: ream) as a plain single-step scene (bmScene.h), on the bone as
  /// the CT gives it.
  nlohmann::json StepSceneJson(int i, const nlohmann::json& bone) const;
  /// The bone object of a scene for a CT at `ctPath` (relative to the scene's folder or
  /// absolute): the glenoid's bone only (seed 1 mm under the centre), in the box of +- roiHalfMm.
  nlohmann::json CtBoneJson(const std::string& ctPath) const;
  /// The same with the CT's import settings the plan was made from: `importSettings` is a scene
  /// bone's "ct" object (bmImport.h ImportOptionsFromJson keys, "ct" = the CT's path): its
  /// intensity ("rawThreshold", "huMapping"), "threshold", "series", "exclude" and the other
  /// import keys are kept, its region ("roi", "box"), "seed", "resolution" and
  /// "keepAllComponents" are the plan's. Throws std::invalid_argument without a "ct" path.
  nlohmann::json CtBoneJsonWithSettings(const nlohmann::json& importSettings) const;
  nlohmann::json ToJson() const;
};

/// The plan's "planning" block as the plan scene carries it: GlenoidPlan::ToJson with the
/// landmarks ("landmarks": GlenoidLandmarks::ToJson) and the measurements ("measurements"). What
/// the glyphs (bmPlanGlyphs.h) and the pictures draw.
nlohmann::json PlanningJson(const GlenoidLandmarks& landmarks, const GlenoidMeasurements& m,
                            const GlenoidPlan& plan);

/// A plan's scenes, as both faces write them (bmsim plan's plan.json, step1-guide-pin.json,
/// step2-ream.json; the plugin's plan filter): on the bone read with `importSettings`
/// (GlenoidPlan::CtBoneJsonWithSettings), the plan scene carrying the landmarks and measurements
/// under "planning" (edit them and plan again with --landmarks).
struct PlanScenes {
  nlohmann::json plan, pin, ream;
};
PlanScenes MakePlanScenes(const GlenoidLandmarks& landmarks, const GlenoidMeasurements& m,
                          const GlenoidPlan& plan, const nlohmann::json& importSettings);

/// The plan's tool would start inside bone (CheckToolStartsOutsideBone).
struct PlanBlocked : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Bone of the glenoid's scapula (landmarks.scapulaLabel) in the reamer's path where the tool
/// starts: within the reamer's radius of the axis, from the start (clearanceMm above the centre,
/// or the highest a glenoid's rim rises, 6 mm plus the face's tilt over the reamer's radius, when
/// that is lower) to 20 mm beyond it. A scene with bone there would start its tool inside bone and
/// ream bone that is not the glenoid (a humeral head joined to the scapula at the threshold, say).
/// Throws PlanBlocked naming the volume (mm^3), where it is and what to do, when it exceeds one
/// voxel.
void CheckToolStartsOutsideBone(const SegmentedBone& bone, const GlenoidLandmarks& landmarks,
                                const GlenoidPlan& plan);

/// Plan from the landmarks and measurements. Throws std::invalid_argument on bad options.
GlenoidPlan MakeGlenoidPlan(const GlenoidLandmarks& landmarks, const GlenoidMeasurements& m,
                            const PlanOptions& options = {});

} // namespace bm
