#include "bmPlanReport.h"
#include "bmHtmlEscape.h"

#include <cmath>
#include <sstream>
#include <vector>

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

const char* kFrame = "Coordinates: world mm in the CT's DICOM LPS frame (x left, y posterior, z "
                     "superior); angles in degrees, negative version = retroversion, positive "
                     "inclination = superior tilt.";

using Table = std::vector<std::vector<std::string>>; // first row: the header

/// The report's content, rendered as Markdown or HTML.
struct Content {
  std::string failure;
  Table landmarks, measurements;
  std::vector<std::string> plan, warnings;
};

Content Build(const PlanReportInput& in) {
  Content c;
  if (!in.landmarks || !in.measurements || !in.plan) {
    c.failure = in.failure;
    return c;
  }
  const GlenoidLandmarks& L = *in.landmarks;
  const GlenoidMeasurements& m = *in.measurements;
  const GlenoidPlan& p = *in.plan;
  c.landmarks = {{"landmark", "position (mm)", "source"},
                 {"glenoid centre", P(L.glenoidCentre), L.centreSource},
                 {"face normal", P(L.faceNormal, 3), L.normalSource},
                 {"trigonum", L.HasTrigonum() ? P(L.trigonum) : "not available",
                  L.HasTrigonum() ? L.trigonumSource : L.trigonumMissing},
                 {"inferior angle", L.HasInferiorAngle() ? P(L.inferiorAngle) : "not available",
                  L.HasInferiorAngle() ? L.inferiorSource : L.inferiorMissing}};
  if (!L.rimMissing.empty())
    c.landmarks.push_back({"rim", "not available", L.rimMissing});
  if (L.humeralHeadFound)
    c.landmarks.push_back({"humeral head centre (radius " + F(L.humeralHeadRadiusMm) + " mm)",
                           P(L.humeralHeadCentre), "detected"});
  const bool t = !in.truth.is_null();
  auto truth = [&](const char* key) {
    return t && in.truth.contains(key) ? F(in.truth[key].get<double>()) : std::string("-");
  };
  // A measurement not available shows why in place of its method.
  auto row = [&](const char* name, const char* key, double v, const char* unit,
                 const char* method) -> std::vector<std::string> {
    const auto why = m.notAvailable.find(key);
    if (why != m.notAvailable.end())
      return {name, "not available", why->second, truth(key)};
    return {name, F(v) + " " + unit, method, truth(key)};
  };
  c.measurements = {
      {"measurement", "value", "method"},
      row("version, Friedman 2D", "friedman_version_deg", m.friedmanVersionDeg, "deg",
          "Friedman 1992, axial slice through the glenoid centre"),
      row("version, 3D", "version_3d_deg", m.version3DDeg, "deg",
          "rim plane normal against the scapular plane (two-plane method)"),
      row("inclination, 3D", "inclination_deg", m.inclinationDeg, "deg",
          "rim plane normal within the scapular plane"),
      row("glenoid height", "glenoid_height_mm", m.heightMm, "mm",
          m.hasFrame ? "rim extent, superior-inferior"
                     : "rim extent along the CT's superior axis (no scapular plane)"),
      row("glenoid width", "glenoid_width_mm", m.widthMm, "mm", "rim extent, anterior-posterior"),
      row("radius of curvature", "face_radius_mm", m.faceRadiusMm, "mm",
          "least-squares sphere of the face")};
  if (t)
    c.measurements[0].push_back("phantom truth");
  else
    for (auto& row : c.measurements)
      row.resize(3);
  c.plan = {"Target: version " + F(p.options.targetVersionDeg) + " deg, inclination " +
                F(p.options.targetInclinationDeg) + " deg.",
            "Reaming axis through the glenoid centre " + P(p.entry) + " mm, direction " +
                P(p.axis, 4) + " (out of the bone): " +
                (p.corrected ? "version " + F(p.axisVersionDeg) + " deg, inclination " +
                                   F(p.axisInclinationDeg) + " deg; correction " +
                                   F(p.correctionDeg) + " deg from the face."
                             : std::string("the face normal, not corrected (no scapular plane).")),
            "Step 1, guide pin: " + F(2 * p.options.pinRadiusMm) + " mm drill, " + F(p.pinDepthMm) +
                " mm deep along the axis.",
            "Step 2, ream: " + F(p.options.reamerDiameterMm) + " mm nipple-guided reamer, " +
                F(p.options.reamDepthMm) + " mm below the centre.",
            std::isfinite(p.reamerOverhangApMm)
                ? "Reamer size: " +
                      std::string(p.reamerFits ? "within the glenoid" : "overhangs the glenoid") +
                      " (overhang " + F(p.reamerOverhangApMm) + " mm anterior-posterior, " +
                      F(p.reamerOverhangSiMm) + " mm superior-inferior per side)."
                : std::string("Reamer size: not checked (no rim).")};
  c.warnings = p.warnings;
  return c;
}

void MdTable(std::ostringstream& md, const Table& t) {
  for (size_t r = 0; r < t.size(); ++r) {
    md << "|";
    for (const auto& cell : t[r])
      md << " " << cell << " |";
    md << "\n";
    if (r == 0) {
      md << "|";
      for (size_t k = 0; k < t[0].size(); ++k)
        md << "---|";
      md << "\n";
    }
  }
}

void HtmlTable(std::ostringstream& h, const Table& t) {
  h << "<table>\n";
  for (size_t r = 0; r < t.size(); ++r) {
    h << "<tr>";
    for (const auto& cell : t[r])
      h << (r == 0 ? "<th>" : "<td>") << HtmlEscape(cell) << (r == 0 ? "</th>" : "</td>");
    h << "</tr>\n";
  }
  h << "</table>\n";
}

} // namespace

nlohmann::json PlanReportJson(const PlanReportInput& in) {
  nlohmann::json j;
  j["source"] = in.source;
  j["frame"] = "world mm, the CT's DICOM LPS frame (x left, y posterior, z superior)";
  if (!in.landmarks || !in.measurements || !in.plan) {
    j["status"] = "no_glenoid";
    j["message"] = in.failure;
    if (!in.failurePicture.empty())
      j["picture"] = in.failurePicture;
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
  const Content c = Build(in);
  std::ostringstream md;
  md << "# Glenoid plan\n\nCT: `" << in.source << "`  \n" << kFrame << "\n\n";
  if (!in.importSummary.empty())
    md << "```\n" << in.importSummary << (in.importSummary.back() == '\n' ? "" : "\n") << "```\n\n";
  if (c.landmarks.empty()) {
    md << "## No plan: " << c.failure << "\n\n";
    if (!in.failurePicture.empty())
      md << "![The bone searched, seen from the front; each joint the message names is marked "
            "with its number]("
         << in.failurePicture << ")\n\n";
    md << "Place these landmarks in a JSON file and plan again with `--landmarks FILE`:\n\n";
    for (const auto& [k, v] : kToPlace.items())
      md << "- `" << k << "`: " << v.get<std::string>() << "\n";
    return md.str();
  }
  md << "## Landmarks\n\n";
  MdTable(md, c.landmarks);
  md << "\n## Measurements\n\n";
  MdTable(md, c.measurements);
  md << "\n## Plan\n\n";
  for (const auto& item : c.plan)
    md << "- " << item << "\n";
  if (!c.warnings.empty()) {
    md << "\n## Warnings\n\n";
    for (const auto& w : c.warnings)
      md << "- " << w << "\n";
  }
  return md.str();
}

std::string PlanReportHtml(const PlanReportInput& in) {
  const Content c = Build(in);
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Glenoid plan</title>\n"
       "<style>body{font-family:sans-serif;max-width:60em;margin:2em auto}"
       "table{border-collapse:collapse}td,th{border:1px solid #999;padding:.2em .5em}"
       ".warn{color:#a00}</style></head><body>\n"
    << "<h1>Glenoid plan</h1>\n<p>CT: <code>" << HtmlEscape(in.source) << "</code><br>"
    << HtmlEscape(kFrame) << "</p>\n";
  if (!in.importSummary.empty())
    h << "<pre>" << HtmlEscape(in.importSummary) << "</pre>\n";
  if (c.landmarks.empty()) {
    h << "<h2 class=\"warn\">No plan: " << HtmlEscape(c.failure) << "</h2>\n";
    if (!in.failurePicture.empty())
      h << "<p><img src=\"" << HtmlEscape(in.failurePicture)
        << "\" alt=\"The bone searched, seen from the front\" width=\"600\"><br>The bone "
           "searched, seen from the front (the patient's left on the right); each joint the "
           "message names is marked with its number.</p>\n";
    h << "<p>Place these landmarks in a JSON file and plan again with <code>--landmarks "
         "FILE</code>:</p>\n<ul>\n";
    for (const auto& [k, v] : kToPlace.items())
      h << "<li><code>" << HtmlEscape(k) << "</code>: " << HtmlEscape(v.get<std::string>())
        << "</li>\n";
    h << "</ul>\n</body></html>\n";
    return h.str();
  }
  h << "<h2>Landmarks</h2>\n";
  HtmlTable(h, c.landmarks);
  h << "<h2>Measurements</h2>\n";
  HtmlTable(h, c.measurements);
  h << "<h2>Plan</h2>\n<ul>\n";
  for (const auto& item : c.plan)
    h << "<li>" << HtmlEscape(item) << "</li>\n";
  h << "</ul>\n";
  if (!c.warnings.empty()) {
    h << "<h2>Warnings</h2>\n<ul class=\"warn\">\n";
    for (const auto& w : c.warnings)
      h << "<li>" << HtmlEscape(w) << "</li>\n";
    h << "</ul>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

} // namespace bm
