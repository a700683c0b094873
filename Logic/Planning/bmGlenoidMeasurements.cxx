#include "bmGlenoidMeasurements.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <stdexcept>

namespace bm {

GlenoidMeasurements MeasureGlenoid(const GlenoidLandmarks& L) {
  GlenoidMeasurements m;
  m.frame = MakeScapularFrame(L.glenoidCentre, L.trigonum, L.inferiorAngle);
  m.version3DDeg = Version3DDeg(m.frame, L.faceNormal);
  m.inclinationDeg = InclinationDeg(m.frame, L.faceNormal);
  m.friedmanVersionDeg =
      FriedmanVersionDeg(L.rim, L.glenoidCentre, L.trigonum, &m.anteriorRim, &m.posteriorRim);
  const Vec3& n = L.faceNormal;
  const Vec3 eu = Normalized(AddScaled(m.frame.superior, n, -Dot(m.frame.superior, n)));
  const Vec3 ev = Cross(n, eu);
  double u0 = 1e30, u1 = -1e30, v0 = 1e30, v1 = -1e30;
  for (const auto& p : L.rim) {
    const Vec3 d = Sub(p, L.glenoidCentre);
    u0 = std::min(u0, Dot(d, eu)), u1 = std::max(u1, Dot(d, eu));
    v0 = std::min(v0, Dot(d, ev)), v1 = std::max(v1, Dot(d, ev));
  }
  m.heightMm = u1 - u0;
  m.widthMm = v1 - v0;
  m.rimPlaneRmsMm = FitRimPlane(L.rim).rmsMm;
  if (L.face.size() < 8)
    throw std::runtime_error("too few articular face points (" + std::to_string(L.face.size()) +
                             ") to fit the face's sphere");
  const SphereFit s = FitSphere(L.face);
  m.faceRadiusMm = s.radiusMm;
  m.faceSphereRmsMm = s.rmsMm;
  return m;
}

nlohmann::json GlenoidMeasurements::ToJson() const {
  return {{"friedman_version_deg", friedmanVersionDeg},
          {"version_3d_deg", version3DDeg},
          {"inclination_deg", inclinationDeg},
          {"glenoid_height_mm", heightMm},
          {"glenoid_width_mm", widthMm},
          {"face_radius_mm", faceRadiusMm},
          {"face_sphere_rms_mm", faceSphereRmsMm},
          {"rim_plane_rms_mm", rimPlaneRmsMm},
          {"friedman_anterior_rim_mm", anteriorRim},
          {"friedman_posterior_rim_mm", posteriorRim},
          {"scapular_frame",
           {{"origin_mm", frame.origin},
            {"lateral", frame.lateral},
            {"anterior", frame.anterior},
            {"superior", frame.superior}}},
          {"methods",
           {{"friedman_version", "Friedman et al. 1992, 2D on the axial plane through the glenoid "
                                 "centre"},
            {"version_3d", "two-plane method: face (rim) plane normal against the scapular plane "
                           "through glenoid centre, trigonum and inferior angle"},
            {"inclination", "face (rim) plane normal's tilt within the scapular plane"},
            {"face_radius", "least-squares sphere of the articular face"}}}};
}

} // namespace bm
