// bmGlenoidLandmarks.h - the glenoid and the scapular-plane landmarks found on a segmented
// shoulder (Docs/Planning.md, "Landmarks"), each of which the user may replace.
//
// Detection on a SegmentedBone (world mm, LPS):
//  1. the joint: surface points of one bone whose outward normal meets another bone within
//     maxJointGapMm; of each pair of bones facing each other, the glenoid side is the concave
//     patch (the centre of its best-fit sphere lies outside the bone) and the other is the
//     humeral head (its surface near the joint fits a sphere of radius 12-40 mm). The patch must
//     span at least minFaceHeightMm x minFaceWidthMm. Nothing found: NoGlenoidFound;
//  2. the rim, by support direction around the axis from the patch toward the head's centre (72
//     points; bmGlenoidGeometry.h), its least-squares plane (normal turned toward the head), and
//     again around the new axis until it settles (kRimIterations); the centre: the face's mean
//     height within 2.5 mm of the rim plane's normal through the rim centroid; the face: the
//     scapula's surface points inside the rim (80 % of its radius) whose normal is within 60 deg of
//     the face normal;
//  3. the scapular-plane landmarks on the scapula (the glenoid's bone): the trigonum T = the
//     medial end of the scapula on the axial plane through the glenoid centre (the centroid of the
//     bone within 3 mm of its point farthest from the centre, on the two slices around the plane,
//     interpolated; Friedman's "medial tip"), the inferior angle I = the centroid of the bone
//     within 5 mm of its point farthest from the glenoid centre among those at least 20 mm
//     below it (the inferior angle lies about 100 mm inferior and medial of the glenoid, arms up
//     or down; the superior angle, as far away, lies above it). Each must lie >= 50 mm from the
//     centre (a scapular body reaches about 100 mm); one that does not, or is out of the scan,
//     is not available, with its reason (trigonumMissing, inferiorMissing): the measurements that
//     need it are not made and the plan is made from the rest (bmGlenoidPlan.h).
// Limits follow the scan: the joint patch's minimum size gives up one voxel at each edge
// (partial volume), the head's sphere-fit residual allows half the CT's coarsest spacing (the
// staircase of thick slices), both from DetectionOptions::scanSpacingMm.
// Overrides (LandmarkOverrides, from the plan's "landmarks" JSON) replace a landmark before the
// steps that depend on it: a given centre and normal skip step 1 (the bone nearest the centre is
// the scapula) and are kept as given, and then a rim that cannot be traced is not available
// instead of a failure; a given normal that points into the bone (the scapula ahead of the face,
// none behind it) is refused. A centre given alone takes the normal of the joint found within
// 15 mm of it, else of the face around it. A given T or I is used as given.
// A side (DetectionOptions::side) keeps only joints whose face looks toward that side: a right
// glenoid faces the patient's right (-x in LPS), a left one +x.
#pragma once

#include "bmSegmentedBone.h"
#include "bmVec3.h"

#include <nlohmann/json_fwd.hpp>

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace bm {

/// Detection failed: the message says what was not found and which landmarks to place;
/// `rejectedAt` holds where each joint the message names lies (world mm, in its order: the
/// rejected pairs' joint patches, or both shoulders' glenoids), for a picture of the failure.
struct NoGlenoidFound : std::runtime_error {
  explicit NoGlenoidFound(const std::string& what, std::vector<Vec3> at = {})
      : std::runtime_error(what), rejectedAt(std::move(at)) {}
  std::vector<Vec3> rejectedAt;
};

struct LandmarkOverrides {
  std::optional<Vec3> glenoidCentre; ///< "glenoid_centre_mm": [x, y, z], world mm
  std::optional<Vec3> faceNormal;    ///< "face_normal": [x, y, z] (normalised), out of the joint
  std::optional<Vec3> trigonum;      ///< "trigonum_mm"
  std::optional<Vec3> inferiorAngle; ///< "inferior_angle_mm"
  /// Rim points (world mm) clicked on the glenoid's edge: with three or more and no centre or
  /// normal, the centre and normal are those of the rim's plane (the normal turned out of the
  /// bone). "rim_points_mm": [[x, y, z], ...].
  std::vector<Vec3> rimPoints;
  /// A point clicked on the glenoid face (world mm; "face_point_mm"), with no centre or normal
  /// given: the glenoid whose joint lies within 15 mm of it, else (no joint: the humeral head out
  /// of the scan or fused to the glenoid) the face around it, traced as detection does (the
  /// face's mean normal within 8 mm starts the rim search; the centre and normal are then the
  /// rim's, not the click's).
  std::optional<Vec3> facePoint;
  bool Empty() const {
    return !glenoidCentre && !faceNormal && !trigonum && !inferiorAngle && rimPoints.empty() &&
           !facePoint;
  }
  /// From a JSON object with any of the keys above (GlenoidLandmarks::ToJson's "source",
  /// "rim_mm", "humeral_head", "side" and "not_available" are skipped, so a plan's landmarks can
  /// be edited and read back); throws std::invalid_argument naming a key that is not an array of 3
  /// finite numbers, an unknown key, or a zero normal.
  static LandmarkOverrides FromJson(const nlohmann::json& j);
};

/// Which shoulder to plan (LPS: the patient's left is +x).
enum class ShoulderSide { Any, Left, Right };
/// "left", "right" or "any".
const char* ShoulderSideName(ShoulderSide side);

struct DetectionOptions {
  ShoulderSide side = ShoulderSide::Any; ///< keep only the glenoid of this shoulder
  /// The CT's coarsest voxel spacing, mm (slice thickness on most CTs); 0 (default): the
  /// segmented bone's own spacing. The limits below allow for it.
  double scanSpacingMm = 0;
  /// The CT's bounds, world mm, when known: a scapular landmark whose tip lies within one scan
  /// spacing of an edge of the scan is where the scapula leaves the field of view, not the
  /// landmark, and is not available.
  std::optional<Box3> scanBounds;
  double maxJointGapMm = 12.0;   ///< farthest the humeral head may be from the face, mm
  double minFaceHeightMm = 20.0; ///< smallest joint patch accepted, mm (long axis)
  double minFaceWidthMm = 12.0;  ///< mm (short axis)
  int rimPoints = 72;            ///< rim points by support direction
  double rimSearchRadiusMm = 35; ///< rim points lie within this of the axis, mm
};

struct GlenoidLandmarks {
  Vec3 glenoidCentre{}, faceNormal{}, trigonum{}, inferiorAngle{};
  std::vector<Vec3> rim;  ///< closed rim polygon, world mm
  std::vector<Vec3> face; ///< articular face points (for the sphere fit)
  bool humeralHeadFound = false;
  Vec3 humeralHeadCentre{};
  double humeralHeadRadiusMm = 0;
  int scapulaLabel = 0;
  std::string side; ///< "left" or "right": the side the face looks toward (LPS x)
  /// Why a landmark is not available ("" = it is): the trigonum or inferior angle outside the
  /// scan or too close to the centre, a rim that could not be traced around a given centre.
  std::string trigonumMissing, inferiorMissing, rimMissing;
  bool HasTrigonum() const { return trigonumMissing.empty(); }
  bool HasInferiorAngle() const { return inferiorMissing.empty(); }
  /// Per landmark ("glenoid_centre", "face_normal", "trigonum", "inferior_angle"): "detected"
  /// or "user".
  std::string centreSource, normalSource, trigonumSource, inferiorSource;
  /// Landmarks as JSON (the keys of LandmarkOverrides plus "rim_mm", "humeral_head", "source",
  /// "side"; a landmark not available is left out and named in "not_available" with its reason).
  nlohmann::json ToJson() const;
};

/// Find the landmarks (see the file comment). Throws NoGlenoidFound when the glenoid cannot be
/// found and was not given (or a given one cannot be used); a scapular landmark that cannot be
/// found is not available (GlenoidLandmarks::trigonumMissing, inferiorMissing).
GlenoidLandmarks DetectLandmarks(const SegmentedBone& bone, const LandmarkOverrides& overrides = {},
                                 const DetectionOptions& options = {});

} // namespace bm
