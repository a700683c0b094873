// bmGlenoidMeasurements.h - what a shoulder surgeon plans by, measured from the landmarks
// (Docs/Planning.md, "Measurements", names each method and its source): Friedman's 2D version on
// the axial plane through the glenoid centre, 3D version and inclination against the scapular
// plane (two-plane method), glenoid height and width along the rim, and the face's radius of
// curvature (least-squares sphere). Angles in deg, lengths in mm.
#pragma once

#include "bmGlenoidGeometry.h"
#include "bmGlenoidLandmarks.h"

#include <nlohmann/json_fwd.hpp>

namespace bm {

struct GlenoidMeasurements {
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
  nlohmann::json ToJson() const;
};

/// Measure (see the file comment). Throws std::runtime_error when the landmarks do not allow a
/// measurement (fewer than 8 face points, a rim that does not cross the mid-glenoid slice).
GlenoidMeasurements MeasureGlenoid(const GlenoidLandmarks& landmarks);

} // namespace bm
