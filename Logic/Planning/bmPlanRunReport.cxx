#include "bmPlanRunReport.h"
#include "bmHtmlEscape.h"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <vector>

#include "bmVec3.h"

namespace bm {
namespace {

constexpr double kRad = 180.0 / 3.14159265358979323846;

std::string Num(const nlohmann::json& j, int digits = 1) {
  if (!j.is_number())
    return "n/a";
  std::ostringstream o;
  o << std::fixed << std::setprecision(digits) << j.get<double>();
  return o.str();
}

const nlohmann::json& At(const nlohmann::json& j, std::initializer_list<const char*> path) {
  static const nlohmann::json null;
  const nlohmann::json* p = &j;
  for (const char* k : path) {
    if (!p->is_object() || !p->contains(k))
      return null;
    p = &p->at(k);
  }
  return *p;
}

Vec3 ToVec(const nlohmann::json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

// The report's rows: a title, then (label, value) pairs per section.
struct Section {
  std::string title;
  std::vector<std::pair<std::string, std::string>> rows;
  std::vector<std::string> notes;
};

// "NAME (calibrated)" or "NAME (not calibrated)" from a summary's "coefficients"
// (ForceModel::ProvenanceJson); "-" when the summary has none.
std::string CoefficientSet(const nlohmann::json& c) {
  if (!c.is_object() || !c.contains("name") || !c.at("name").is_string())
    return "-";
  const bool calibrated = c.value("calibrated", false);
  return c.at("name").get<std::string>() + (calibrated ? " (calibrated)" : " (not calibrated)");
}

std::vector<Section> Sections(const nlohmann::json& s) {
  std::vector<Section> out;
  const nlohmann::json& m = At(s, {"planning", "measurements"});
  const nlohmann::json& p = s.value("planning", nlohmann::json::object());
  Section pre{"Pre-operative glenoid", {}, {}};
  pre.rows = {{"Version, Friedman 2D (deg)", Num(At(m, {"friedman_version_deg"}))},
              {"Version, 3D against the scapular plane (deg)", Num(At(m, {"version_3d_deg"}))},
              {"Inclination, 3D (deg)", Num(At(m, {"inclination_deg"}))},
              {"Glenoid height x width (mm)",
               Num(At(m, {"glenoid_height_mm"})) + " x " + Num(At(m, {"glenoid_width_mm"}))},
              {"Face radius of curvature (mm)", Num(At(m, {"face_radius_mm"}))}};
  out.push_back(pre);
  Section plan{"Plan", {}, {}};
  plan.rows = {{"Target version / inclination (deg)", Num(At(p, {"target_version_deg"})) + " / " +
                                                          Num(At(p, {"target_inclination_deg"}))},
               {"Axis correction (deg)", Num(At(p, {"correction_deg"}))},
               {"Reaming depth below the centre (mm)", Num(At(p, {"ream_depth_mm"}))},
               {"Guide pin radius x depth (mm)",
                Num(At(p, {"pin_radius_mm"})) + " x " + Num(At(p, {"pin_depth_mm"}))}};
  if (p.contains("warnings"))
    for (const auto& w : p.at("warnings"))
      plan.notes.push_back(w.get<std::string>());
  out.push_back(plan);
  for (const auto& st : s.value("steps", nlohmann::json::array())) {
    const nlohmann::json& ss = st.at("summary");
    Section step{"Step " + std::to_string(st.value("step", 0)) + ": " +
                     st.value("name", std::string()) + " (" + st.value("tool", std::string()) + ")",
                 {},
                 {}};
    step.rows = {{"Reached depth (mm)", Num(At(ss, {"reached_depth_mm"}), 2)},
                 {"Removed volume (mm^3)", Num(At(ss, {"removed_volume_mm3"}))},
                 {"Mean thrust (N)", Num(At(ss, {"thrust_N"}))},
                 {"Mean torque (N mm)", Num(At(ss, {"torque_Nmm"}))},
                 {"Coefficient set", CoefficientSet(At(ss, {"coefficients"}))}};
    // A step run as a session in the viewer has no folder of its own.
    if (!st.value("folder", std::string()).empty())
      step.rows.push_back(
          {"Forces over time, cut surface", st.value("folder", std::string()) + "/report.html"});
    for (const auto& w : ss.value("warnings", nlohmann::json::array()))
      step.notes.push_back(w.get<std::string>());
    out.push_back(step);
  }
  const nlohmann::json& o = At(s, {"outcome"});
  if (!o.is_null()) {
    const nlohmann::json& opt = At(o, {"options"});
    Section res{"Outcome", {}, {}};
    res.rows = {
        {"Removed bone: cortical / cancellous (mm^3)",
         Num(At(o, {"removed_cortical_mm3"})) + " / " + Num(At(o, {"removed_cancellous_mm3"}))},
        {"Reamed face: angle to the planned axis (deg)",
         Num(At(o, {"reamed_face_angle_to_axis_deg"}), 2)},
        {"Reamed face: version / inclination (deg)",
         Num(At(o, {"reamed_face_version_deg"})) + " / " +
             Num(At(o, {"reamed_face_inclination_deg"}))},
        {"Reamed face against the target: version / inclination (deg)",
         Num(At(o, {"reamed_face_version_error_deg"})) + " / " +
             Num(At(o, {"reamed_face_inclination_error_deg"}))},
        {"Medialisation of the joint line (mm)", Num(At(o, {"medialisation_mm"}), 2)},
        {"Baseplate seating: back within " + Num(At(opt, {"seating_gap_mm"})) + " mm of bone (" +
             Num(At(opt, {"baseplate_diameter_mm"}), 0) + " mm baseplate)",
         Num(nlohmann::json(100.0 * At(o, {"seating_fraction"}).get<double>()), 0) + " %"},
        {"Bone beyond the guide pin's tip (mm)", Num(At(o, {"bone_beyond_pin_mm"}))},
        {"Bone beyond the central peg's tip (" + Num(At(opt, {"peg_length_mm"}), 0) +
             " mm peg, mm)",
         Num(At(o, {"bone_beyond_peg_mm"}))}};
    for (const auto& w : o.value("warnings", nlohmann::json::array()))
      res.notes.push_back(w.get<std::string>());
    out.push_back(res);
  }
  return out;
}

} // namespace

nlohmann::json WithFaceAngles(nlohmann::json s) {
  const nlohmann::json& frame = At(s, {"planning", "measurements", "scapular_frame"});
  if (!s.contains("outcome") || !frame.is_object() || !frame.contains("lateral"))
    return s;
  const Vec3 n = ToVec(s["outcome"].at("reamed_face_normal"));
  const Vec3 lat = ToVec(frame.at("lateral")), ant = ToVec(frame.at("anterior")),
             sup = ToVec(frame.at("superior"));
  const double version = std::atan2(Dot(n, ant), Dot(n, lat)) * kRad;
  const double inclination = std::atan2(Dot(n, sup), Dot(n, lat)) * kRad;
  nlohmann::json& o = s["outcome"];
  o["reamed_face_version_deg"] = version;
  o["reamed_face_inclination_deg"] = inclination;
  const nlohmann::json& p = s["planning"];
  if (p.contains("target_version_deg") && p.contains("target_inclination_deg")) {
    o["reamed_face_version_error_deg"] = version - p["target_version_deg"].get<double>();
    o["reamed_face_inclination_error_deg"] =
        inclination - p["target_inclination_deg"].get<double>();
  }
  return s;
}

std::string PlanRunMarkdown(const nlohmann::json& summary) {
  std::ostringstream md;
  md << "# Plan rehearsed: " << summary.value("plan", std::string("plan")) << "\n\n"
     << (summary.value("completed", false)
             ? "Both steps ran to their planned depths on one bone.\n"
             : "**The plan did not complete:** a step stopped early (see its warning).\n");
  for (const Section& sec : Sections(summary)) {
    md << "\n## " << sec.title << "\n\n| | |\n|---|---|\n";
    for (const auto& [k, v] : sec.rows)
      md << "| " << k << " | " << v << " |\n";
    for (const std::string& n : sec.notes)
      md << "\n**Warning:** " << n << "\n";
  }
  if (summary.contains("pictures")) {
    md << "\n## The glenoid before and after\n\nRed: the planned reaming axis; green: the "
          "measured face normal; yellow: the rim; white: the planned face plane at the reamer's "
          "radius.\n\n";
    for (const char* when : {"before", "after"})
      if (summary["pictures"].contains(when))
        md << "![" << when << "](" << summary["pictures"][when].get<std::string>() << ")\n";
  }
  md << "\nMethods: Docs/Planning.md (measurements and the outcome).\n";
  return md.str();
}

std::string PlanRunHtml(const nlohmann::json& summary) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Plan rehearsed</title>"
       "<style>body{font-family:sans-serif;max-width:60em;margin:2em auto}"
       "table{border-collapse:collapse}td{border:1px solid #ccc;padding:.3em .6em}"
       ".warn{color:#a00}</style></head><body>\n"
    << "<h1>Plan rehearsed: " << HtmlEscape(summary.value("plan", std::string("plan")))
    << "</h1>\n<p>"
    << (summary.value("completed", false)
            ? "Both steps ran to their planned depths on one bone."
            : "<b class=\"warn\">The plan did not complete:</b> a step stopped early.")
    << "</p>\n";
  for (const Section& sec : Sections(summary)) {
    h << "<h2>" << HtmlEscape(sec.title) << "</h2>\n<table>\n";
    for (const auto& [k, v] : sec.rows) {
      const bool link = v.size() > 12 && v.compare(v.size() - 12, 12, "/report.html") == 0;
      h << "<tr><td>" << HtmlEscape(k) << "</td><td>"
        << (link ? "<a href=\"" + HtmlEscape(v) + "\">" + HtmlEscape(v) + "</a>" : HtmlEscape(v))
        << "</td></tr>\n";
    }
    h << "</table>\n";
    for (const std::string& n : sec.notes)
      h << "<p class=\"warn\">Warning: " << HtmlEscape(n) << "</p>\n";
  }
  if (summary.contains("pictures")) {
    h << "<h2>The glenoid before and after</h2>\n<p>Red: the planned reaming axis; green: the "
         "measured face normal; yellow: the rim; white: the planned face plane at the reamer's "
         "radius.</p>\n<p>";
    for (const char* when : {"before", "after"})
      if (summary["pictures"].contains(when))
        h << "<img src=\"" << HtmlEscape(summary["pictures"][when].get<std::string>())
          << "\" alt=\"" << when << "\" width=\"400\"> ";
    h << "</p>\n";
  }
  h << "</body></html>\n";
  return h.str();
}

} // namespace bm
