#include "bmGlenoidMeasurements.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

namespace bm {

GlenoidMeasurements MeasureGlenoid(const GlenoidLandmarks& L) {
  GlenoidMeasurements m;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.friedmanVersionDeg = m.version3DDeg = m.inclinationDeg = nan;
  m.heightMm = m.widthMm = m.faceRadiusMm = m.faceSphereRmsMm = m.rimPlaneRmsMm = nan;
  auto missing = [&](std::initializer_list<const char*> keys, const std::string& why) {
    for (const char* k : keys)
      m.notAvailable[k] = why;
  };
  const Vec3& n = L.faceNormal;
  std::string noFrame;
  if (!L.HasTrigonum())
    noFrame = "no trigonum (" + L.trigonumMissing + ")";
  else if (!L.HasInferiorAngle())
    noFrame = "no inferior angle (" + L.inferiorMissing + ")";
  else {
    try {
      m.frame = MakeScapularFrame(L.glenoidCentre, L.trigonum, L.inferiorAngle);
      m.hasFrame = true;
    } catch (const std::invalid_argument& e) {
      noFrame = e.what();
    }
  }
  if (m.hasFrame) {
    m.version3DDeg = Version3DDeg(m.frame, n);
    m.inclinationDeg = InclinationDeg(m.frame, n);
  } else {
    missing({"version_3d_deg", "inclination_deg"}, "no scapular plane: " + noFrame);
  }
  if (!L.HasTrigonum())
    missing({"friedman_version_deg"}, "no trigonum (Friedman's medial tip): " + L.trigonumMissing);
  else if (L.rim.empty())
    missing({"friedman_version_deg"}, "no rim: " + L.rimMissing);
  else {
    try {
      m.friedmanVersionDeg =
          FriedmanVersionDeg(L.rim, L.glenoidCentre, L.trigonum, &m.anteriorRim, &m.posteriorRim);
    } catch (const std::runtime_error& e) {
      missing({"friedman_version_deg"}, e.what());
    }
  }
  if (L.rim.size() >= 3) {
    const Vec3 up = m.hasFrame ? m.frame.superior : Vec3{0, 0, 1};
    std::tie(m.heightMm, m.widthMm) = RimExtents(L.rim, L.glenoidCentre, n, up);
    m.rimPlaneRmsMm = FitRimPlane(L.rim).rmsMm;
  } else {
    missing({"glenoid_height_mm", "glenoid_width_mm", "rim_plane_rms_mm"},
            "no rim: " + L.rimMissing);
  }
  std::string noSphere;
  if (L.face.size() < 8)
    noSphere = "too few articular face points (" + std::to_string(L.face.size()) + ")";
  else {
    try {
      const SphereFit s = FitSphere(L.face);
      m.faceRadiusMm = s.radiusMm;
      m.faceSphereRmsMm = s.rmsMm;
    } catch (const std::invalid_argument& e) {
      noSphere = e.what();
    }
  }
  if (!noSphere.empty())
    missing({"face_radius_mm", "face_sphere_rms_mm"}, noSphere);
  return m;
}

nlohmann::json GlenoidMeasurements::ToJson() const {
  auto value = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json j = {
      {"friedman_version_deg", value(friedmanVersionDeg)},
      {"version_3d_deg", value(version3DDeg)},
      {"inclination_deg", value(inclinationDeg)},
      {"glenoid_height_mm", value(heightMm)},
      {"glenoid_width_mm", value(widthMm)},
      {"face_radius_mm", value(faceRadiusMm)},
      {"face_sphere_rms_mm", value(faceSphereRmsMm)},
      {"rim_plane_rms_mm", value(rimPlaneRmsMm)},
      {"friedman_anterior_rim_mm", anteriorRim},
      {"friedman_posterior_rim_mm", posteriorRim},
      {"methods",
       {{"friedman_version", "Friedman et al. 1992, 2D on the axial plane through the glenoid "
                             "centre"},
        {"version_3d", "two-plane method: face (rim) plane normal against the scapular plane "
                       "through glenoid centre, trigonum and inferior angle"},
        {"inclination", "face (rim) plane normal's tilt within the scapular plane"},
        {"face_radius", "least-squares sphere of the articular face"}}}};
  if (hasFrame)
    j["scapular_frame"] = {{"origin_mm", frame.origin},
                           {"lateral", frame.lateral},
                           {"anterior", frame.anterior},
                           {"superior", frame.superior}};
  if (!notAvailable.empty())
    j["not_available"] = notAvailable;
  return j;
}

} // namespace bm
