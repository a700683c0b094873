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
//     within 5 mm of its point farthest from the glenoid centre. Each must lie >= 50 mm from the
//     centre, else NoGlenoidFound names it.
// Overrides (LandmarkOverrides, from the plan's "landmarks" JSON) replace a landmark before the
// steps that depend on it: a given centre and normal skip step 1 (the bone nearest the centre is
// the scapula) and are kept as given; a given T or I is used as given.
#pragma once

#include "bmSegmentedBone.h"
#include "bmVec3.h"

#include <nlohmann/json_fwd.hpp>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace bm {

/// Detection failed: the message says what was not found and which landmarks to place.
struct NoGlenoidFound : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct LandmarkOverrides {
  std::optional<Vec3> glenoidCentre; ///< "glenoid_centre_mm": [x, y, z], world mm
  std::optional<Vec3> faceNormal;    ///< "face_normal": [x, y, z] (normalised), out of the joint
  std::optional<Vec3> trigonum;      ///< "trigonum_mm"
  std::optional<Vec3> inferiorAngle; ///< "inferior_angle_mm"
  bool Empty() const { return !glenoidCentre && !faceNormal && !trigonum && !inferiorAngle; }
  /// From a JSON object with any of the keys above (GlenoidLandmarks::ToJson's "source",
  /// "rim_mm" and "humeral_head" are skipped, so a plan's landmarks can be edited and read
  /// back); throws std::invalid_argument naming a key that is not an array of 3 finite numbers,
  /// an unknown key, or a zero normal.
  static LandmarkOverrides FromJson(const nlohmann::json& j);
};

struct DetectionOptions {
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
  /// Per landmark ("glenoid_centre", "face_normal", "trigonum", "inferior_angle"): "detected"
  /// or "user".
  std::string centreSource, normalSource, trigonumSource, inferiorSource;
  /// Landmarks as JSON (the keys of LandmarkOverrides plus "rim_mm", "humeral_head", "source").
  nlohmann::json ToJson() const;
};

/// Find the landmarks (see the file comment). Throws NoGlenoidFound when the glenoid or a
/// scapular landmark cannot be found and was not given.
GlenoidLandmarks DetectLandmarks(const SegmentedBone& bone, const LandmarkOverrides& overrides = {},
                                 const DetectionOptions& options = {});

} // namespace bm
