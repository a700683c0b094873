// bmGlenoidMeasurements.h - what a shoulder surgeon plans by, measured from the landmarks
// (Docs/Planning.md, "Measurements", names each method and its source): Friedman's 2D version on
// the axial plane through the glenoid centre, 3D version and inclination against the scapular
// plane (two-plane method), glenoid height and width along the rim, and the face's radius of
// curvature (least-squares sphere). Angles in deg, lengths in mm.
//
// A measurement whose landmarks are not available (the trigonum or inferior angle out of the
// scan, a rim that does not cross the axial plane) is NaN and named in notAvailable with its
// reason; the others are still made. Without the scapular frame (trigonum or inferior angle
// missing) the glenoid's height is taken along the CT's superior axis projected on the face.
#pragma once

#include "bmGlenoidGeometry.h"
#include "bmGlenoidLandmarks.h"

#include <nlohmann/json_fwd.hpp>

#include <map>
#include <string>

namespace bm {

struct GlenoidMeasurements {
  bool hasFrame = false;              ///< the scapular frame could be made
  ScapularFrame frame;                ///< from the glenoid centre, trigonum and inferior angle
  double friedmanVersionDeg = 0;      ///< Friedman 2D (negative = retroversion)
  double version3DDeg = 0;            ///< face normal against the scapular plane (transverse)
  double inclinationDeg = 0;          ///< face normal in the scapular plane (positive = superior)
  double heightMm = 0;                ///< rim extent along the face's superior axis
  double widthMm = 0;                 ///< rim extent across it (anterior-posterior)
  double faceRadiusMm = 0;            ///< radius of curvature of the articular face (sphere fit)
  double faceSphereRmsMm = 0;         ///< RMS residual of that fit
  double rimPlaneRmsMm = 0;           ///< RMS distance of the rim from its plane
  Vec3 anteriorRim{}, posteriorRim{}; ///< Friedman's glenoid line ends
  /// Measurement key (ToJson's, e.g. "version_3d_deg") -> why it is not available.
  std::map<std::string, std::string> notAvailable;
  bool Available(const std::string& key) const { return !notAvailable.count(key); }
  /// The values (NaN as null), "scapular_frame" (with one), "methods" and "not_available".
  nlohmann::json ToJson() const;
};

/// Measure (see the file comment); what cannot be measured is not available, never an error.
GlenoidMeasurements MeasureGlenoid(const GlenoidLandmarks& landmarks);

} // namespace bm
