// bmReamingOutcome.h - what a planned pin-and-ream did to the glenoid, measured on the voxmaps
// before the first step and after the last (Docs/Planning.md, "Outcome"):
//  - removed volume, split into cortical and cancellous bone by the voxels' material (material
//    >= kCorticalMaterial, i.e. >= 600 HU under the default HU mapping, counts as cortical);
//  - the reamed face: surface points found along rays parallel to the planned axis (the first
//    voxel at least half full), a least-squares plane through those the reamer cut whose mirror
//    point across the axis was cut too (a face of revolution reamed off-centre stays untilted),
//    its normal's angle to the planned axis, and where the axis crosses it (the face's depth);
//  - medialisation of the joint line: the face height at the centre before minus after: before
//    from a least-squares quadratic over the surface heights within 8 mm of the axis (the guide-pin
//    hole left out), after from the cut points there, each brought to the centre along the
//    reamer's own face profile (their mean; a reamer that cut none there, or a tool that is not an
//    arc reamer: a quadratic too);
//  - backside seating: the fraction of the baseplate's back (a disc of the given diameter less
//    the central peg hole, shaped as the reamer's face or as a sphere of the given back radius,
//    seated at the reached depth) that has bone within `gapMm` of it;
//  - bone remaining beyond the guide pin's and the central peg's tips along the axis before the
//    vault's far cortex ends (the first void run of at least 1 mm), with a perforation warning
//    when it is negative.
// Frames: world mm; `entry` is the glenoid centre on the pre-operative face, `axis` the planned
// reaming axis pointing out of the bone (as in the plan's trial). Heights are along `axis` from
// `entry` (positive = lateral, out of the bone).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bmToolModel.h"
#include "bmVec3.h"
#include "bmVoxmap.h"

namespace bm {

/// Voxels of at least this material scale count as cortical bone.
constexpr double kCorticalMaterial = 0.5;

struct ReamingOutcomeOptions {
  double baseplateDiameterMm = 25.0; ///< baseplate back diameter, mm (default 25)
  double backRadiusMm = 0.0; ///< spherical back radius, mm; 0 = the reamer's own face (default)
  double gapMm = 0.5;        ///< bone within this of the back counts as support, mm (0.5)
  double pegLengthMm = 12.0; ///< central peg length below the reamed face, mm (12)
  double pegRadiusMm = 3.5;  ///< central peg radius, mm (3.5)
  double pinRadiusMm = 1.6;  ///< guide-pin hole radius, mm
  double pinDepthMm = 0.0;   ///< guide-pin hole depth below the entry, mm (0: no pin step)
};

struct ReamingOutcome {
  double reachedDepthMm = 0; ///< the reamer's foremost ring below the entry, mm
  double removedMm3 = 0, removedCorticalMm3 = 0, removedCancellousMm3 = 0;
  Vec3 faceNormal{0, 0, 0}; ///< fitted reamed-face normal (out of the bone)
  double faceAngleDeg = 0;  ///< between faceNormal and the planned axis, deg
  /// Where the axis crosses the fitted reamed-face plane, below the entry, mm (0 when no plane)
  double faceDepthMm = 0;
  int facePoints = 0; ///< surface points the plane was fitted to
  double medialisationMm = 0;
  double seating = 0;         ///< fraction 0..1 of the back's area supported within gapMm
  double boneBeyondPinMm = 0; ///< bone along the axis beyond the pin's tip, mm (< 0: perforated)
  double boneBeyondPegMm = 0; ///< the same beyond the peg's tip, mm
  std::vector<std::string> warnings;
  nlohmann::json ToJson() const;
};

/// Measures the outcome. `reamer` must be the reamer that was used (ArcLipTool; its face shapes the
/// back when backRadiusMm is 0); reachedDepthMm is the reamer trial's reached depth (its summary's
/// reached_depth_mm). Throws std::invalid_argument when the voxmaps differ in grid, the axis is not
/// a unit vector or the options are out of range (all lengths > 0, the peg narrower than the
/// baseplate).
ReamingOutcome MeasureReamingOutcome(const Voxmap& before, const Voxmap& after, const Vec3& entry,
                                     const Vec3& axis, const ToolModel& reamer,
                                     double reachedDepthMm, const ReamingOutcomeOptions& options);

} // namespace bm
