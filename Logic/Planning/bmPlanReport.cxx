#include "bmPlanReport.h"

#include <sstream>

namespace bm {

namespace {

std::string F(double v, int digits = 1) {
  std::ostringstream s;
  s.precision(digits);
  s << std::fixed << v;
  return s.str();
}

std::string P(const Vec3& p, int digits = 1) {
  std::ostringstream s;
  s.precision(digits);
  s << std::fixed << '(' << p[0] << ", " << p[1] << ", " << p[2] << ')';
  return s.str();
}

const nlohmann::json kToPlace = {
    {"glenoid_centre_mm", "the centre of the glenoid's articular face, [x, y, z] world mm"},
    {"face_normal", "the face's outward normal (out of the joint), [x, y, z]"},
    {"trigonum_mm", "the medial end of the scapular spine, [x, y, z] world mm"},
    {"inferior_angle_mm", "the scapula's inferior angle, [x, y, z] world mm"}};

} // namespace

nlohmann::json PlanReportJson(const PlanReportInput& in) {
  nlohmann::json j;
  j["source"] = in.source;
  j["frame"] = "world mm, the CT's DICOM LPS frame (x left, y posterior, z superior)";
  if (!in.landmarks || !in.measurements || !in.plan) {
    j["status"] = "no_glenoid";
    j["message"] = in.failure;
    j["landmarks_to_place"] = kToPlace;
  } else {
    j["status"] = "planned";
    j["landmarks"] = in.landmarks->ToJson();
    j["measurements"] = in.measurements->ToJson();
    j["plan"] = in.plan->ToJson();
  }
  if (!in.truth.is_null())
    j["truth"] = in.truth;
  return j;
}

std::string PlanReportMarkdown(const PlanReportInput& in) {
  std::ostringstream md;
  md << "# Glenoid plan\n\n"
     << "CT: `" << in.source << "`  \n"
     << "Coordinates: world mm in the CT's DICOM LPS frame (x left, y posterior, z superior); "
        "angles in degrees, negative version = retroversion, positive inclination = superior "
        "tilt.\n\n";
  if (!in.importSummary.empty())
    md << "```\n" << in.importSummary << (in.importSummary.back() == '\n' ? "" : "\n") << "```\n\n";
  if (!in.landmarks || !in.measurements || !in.plan) {
    md << "## No plan: " << in.failure << "\n\n"
       << "Place these landmarks in a JSON file and plan again with `--landmarks FILE`:\n\n";
    for (const auto& [k, v] : kToPlace.items())
      md << "- `" << k << "`: " << v.get<std::string>() << "\n";
    return md.str();
  }
  const GlenoidLandmarks& L = *in.landmarks;
  const GlenoidMeasurements& m = *in.measurements;
  const GlenoidPlan& p = *in.plan;
  const bool t = !in.truth.is_null();
  auto truth = [&](const char* key, int digits = 1) -> std::string {
    if (!t || !in.truth.contains(key))
      return "";
    return " | " + F(in.truth[key].get<double>(), digits);
  };
  md << "## Landmarks\n\n| landmark | position (mm) | source |\n|---|---|---|\n"
     << "| glenoid centre | " << P(L.glenoidCentre) << " | " << L.centreSource << " |\n"
     << "| face normal | " << P(L.faceNormal, 3) << " | " << L.normalSource << " |\n"
     << "| trigonum | " << P(L.trigonum) << " | " << L.trigonumSource << " |\n"
     << "| inferior angle | " << P(L.inferiorAngle) << " | " << L.inferiorSource << " |\n";
  if (L.humeralHeadFound)
    md << "| humeral head centre (radius " << F(L.humeralHeadRadiusMm) << " mm) | "
       << P(L.humeralHeadCentre) << " | detected |\n";
  md << "\n## Measurements\n\n| measurement | value | method |" << (t ? " phantom truth |" : "")
     << "\n|---|---|---|" << (t ? "---|" : "") << "\n"
     << "| version, Friedman 2D | " << F(m.friedmanVersionDeg)
     << " deg | Friedman 1992, axial slice through the glenoid centre"
     << truth("friedman_version_deg") << " |\n"
     << "| version, 3D | " << F(m.version3DDeg)
     << " deg | rim plane normal against the scapular plane (two-plane method)"
     << truth("version_3d_deg") << " |\n"
     << "| inclination, 3D | " << F(m.inclinationDeg)
     << " deg | rim plane normal within the scapular plane" << truth("inclination_deg") << " |\n"
     << "| glenoid height | " << F(m.heightMm) << " mm | rim extent, superior-inferior"
     << truth("glenoid_height_mm") << " |\n"
     << "| glenoid width | " << F(m.widthMm) << " mm | rim extent, anterior-posterior"
     << truth("glenoid_width_mm") << " |\n"
     << "| radius of curvature | " << F(m.faceRadiusMm) << " mm | least-squares sphere of the face"
     << truth("face_radius_mm") << " |\n\n"
     << "## Plan\n\n"
     << "- Target: version " << F(p.options.targetVersionDeg) << " deg, inclination "
     << F(p.options.targetInclinationDeg) << " deg.\n"
     << "- Reaming axis through the glenoid centre " << P(p.entry) << " mm, direction "
     << P(p.axis, 4) << " (out of the bone): version " << F(p.axisVersionDeg)
     << " deg, inclination " << F(p.axisInclinationDeg) << " deg; correction " << F(p.correctionDeg)
     << " deg from the face.\n"
     << "- Step 1, guide pin: " << F(2 * p.options.pinRadiusMm) << " mm drill, " << F(p.pinDepthMm)
     << " mm deep along the axis.\n"
     << "- Step 2, ream: " << F(p.options.reamerDiameterMm) << " mm nipple-guided reamer, "
     << F(p.options.reamDepthMm) << " mm below the centre.\n"
     << "- Reamer size: " << (p.reamerFits ? "within the glenoid" : "overhangs the glenoid")
     << " (overhang " << F(p.reamerOverhangApMm) << " mm anterior-posterior, "
     << F(p.reamerOverhangSiMm) << " mm superior-inferior per side).\n";
  if (!p.warnings.empty()) {
    md << "\n## Warnings\n\n";
    for (const auto& w : p.warnings)
      md << "- " << w << "\n";
  }
  return md.str();
}

} // namespace bm
