#include "bmCalibrationData.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "bmToolModel.h"
#include "bmCsv.h"

namespace bm {

namespace {

const std::vector<std::string> kColumns{"tool",
                                        "diameter_mm",
                                        "point_angle_deg",
                                        "helix_angle_deg",
                                        "web_half_width_mm",
                                        "feed_mm_per_rev",
                                        "speed_rpm",
                                        "bone",
                                        "density",
                                        "depth_mm",
                                        "thrust_N",
                                        "torque_Nmm",
                                        "source",
                                        "note"};

double ParseNumber(const std::string& text, const std::string& where, double lo, double hi,
                   const char* range) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(v))
    throw std::invalid_argument(where + ": '" + text + "' is not a number");
  if (v < lo || v > hi)
    throw std::invalid_argument(where + ": " + text + " is out of range (" + range + ")");
  return v;
}

std::string Csv(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos)
    return s;
  std::string q = "\"";
  for (char c : s)
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string Num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

} // namespace

std::vector<CalibrationRecord> ReadCalibrationCsv(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw std::invalid_argument("calibration data " + file.string() +
                                ": not a regular file (a FIFO would block the read)");
  std::ifstream in(file);
  if (!in)
    throw std::invalid_argument("calibration data " + file.string() + ": cannot open");
  std::string line;
  std::vector<std::string> header;
  std::map<std::string, size_t> col;
  std::vector<CalibrationRecord> out;
  std::map<std::string, std::shared_ptr<const ToolModel>> tools;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string where = file.string() + ":" + std::to_string(lineNo);
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#')
      continue;
    std::vector<std::string> f = SplitCsvRecord(line, where);
    if (header.empty()) {
      header = f;
      for (size_t i = 0; i < header.size(); ++i) {
        if (std::find(kColumns.begin(), kColumns.end(), header[i]) == kColumns.end())
          throw std::invalid_argument(where + ": unknown column '" + header[i] + "'");
        if (col.count(header[i]))
          throw std::invalid_argument(where + ": column '" + header[i] + "' appears twice");
        col[header[i]] = i;
      }
      for (const char* need : {"tool", "feed_mm_per_rev", "speed_rpm", "thrust_N"})
        if (!col.count(need))
          throw std::invalid_argument(where + ": missing required column '" + need + "'");
      continue;
    }
    if (f.size() != header.size())
      throw std::invalid_argument(where + ": " + std::to_string(f.size()) + " fields, header has " +
                                  std::to_string(header.size()));
    auto get = [&](const char* name) -> std::string {
      auto it = col.find(name);
      return it == col.end() ? std::string() : f[it->second];
    };
    auto num = [&](const char* name, double lo, double hi, const char* range) {
      return ParseNumber(get(name), where + " column " + name, lo, hi, range);
    };
    auto required = [&](const char* name) {
      if (get(name).empty())
        throw std::invalid_argument(where + ": column " + std::string(name) + " is empty");
    };
    CalibrationRecord r;
    r.line = lineNo;
    const std::string type = get("tool");
    required("tool");
    nlohmann::json spec{{"type", type}};
    const bool hasD = !get("diameter_mm").empty();
    const double d = hasD ? num("diameter_mm", 1e-3, 1e3, "> 0 mm") : 0.0;
    if (type == "drill") {
      if (hasD)
        spec["radius_mm"] = d / 2;
      if (!get("point_angle_deg").empty())
        spec["point_angle_deg"] = num("point_angle_deg", 1, 179, "1..179 deg") / 2;
      if (!get("helix_angle_deg").empty())
        spec["helix_angle_deg"] = num("helix_angle_deg", 0, 89, "0..89 deg");
      if (!get("web_half_width_mm").empty())
        spec["web_half_width_mm"] = num("web_half_width_mm", 1e-3, 1e2, "> 0 mm");
    } else if (type == "reamer" || type == "burr") {
      for (const char* drillOnly : {"point_angle_deg", "helix_angle_deg", "web_half_width_mm"})
        if (!get(drillOnly).empty())
          throw std::invalid_argument(where + ": column " + std::string(drillOnly) +
                                      " applies to drills only");
      if (hasD)
        spec[type == "reamer" ? "outer_radius_mm" : "radius_mm"] = d / 2;
    } else {
      throw std::invalid_argument(where + ": unknown tool '" + type + "' (drill, reamer or burr)");
    }
    auto& tool = tools[spec.dump()];
    if (!tool) {
      try {
        tool = std::shared_ptr<const ToolModel>(MakeTool(spec));
      } catch (const std::exception& e) {
        throw std::invalid_argument(where + ": tool: " + e.what());
      }
    }
    r.toolSpec = spec;
    CalibrationSample& s = r.sample;
    s.tool = tool;
    required("feed_mm_per_rev");
    required("speed_rpm");
    required("thrust_N");
    s.feedMmPerRev = num("feed_mm_per_rev", 1e-6, 10, "> 0 mm/rev");
    s.speedRpm = num("speed_rpm", 1, 1e6, ">= 1 rpm");
    s.thrustN = num("thrust_N", -1e6, 1e6, "a force in N");
    s.torqueNmm = get("torque_Nmm").empty() ? std::numeric_limits<double>::quiet_NaN()
                                            : num("torque_Nmm", -1e7, 1e7, "a torque in N mm");
    s.depthMm = get("depth_mm").empty() ? 1e300 : num("depth_mm", 0, 1e4, ">= 0 mm");
    s.material = get("density").empty() ? 1.0 : num("density", 1e-6, 100, "> 0");
    s.bone = get("bone");
    r.source = get("source");
    r.note = get("note");
    char cond[256];
    std::snprintf(cond, sizeof cond, "%s d=%g f=%g n=%g %s", type.c_str(), 2 * tool->OuterRadius(),
                  s.feedMmPerRev, s.speedRpm, s.bone.c_str());
    s.condition = cond;
    if (!get("density").empty())
      s.condition += " density=" + get("density");
    out.push_back(std::move(r));
  }
  if (header.empty())
    throw std::invalid_argument("calibration data " + file.string() + ": no header line");
  if (out.empty())
    throw std::invalid_argument("calibration data " + file.string() + ": no data rows");
  return out;
}

std::string FormatCalibrationCsv(const std::vector<CalibrationRecord>& records) {
  std::ostringstream os;
  for (size_t i = 0; i < kColumns.size(); ++i)
    os << (i ? "," : "") << kColumns[i];
  os << "\n";
  for (const auto& r : records) {
    const auto& t = r.toolSpec;
    const CalibrationSample& s = r.sample;
    const std::string type = t.value("type", std::string("drill"));
    std::string d, pa, helix, web;
    if (type == "drill") {
      if (t.contains("radius_mm"))
        d = Num(2 * t["radius_mm"].get<double>());
      if (t.contains("point_angle_deg"))
        pa = Num(2 * t["point_angle_deg"].get<double>());
      if (t.contains("helix_angle_deg"))
        helix = Num(t["helix_angle_deg"].get<double>());
      if (t.contains("web_half_width_mm"))
        web = Num(t["web_half_width_mm"].get<double>());
    } else {
      const char* key = type == "reamer" ? "outer_radius_mm" : "radius_mm";
      if (t.contains(key))
        d = Num(2 * t[key].get<double>());
    }
    os << type << "," << d << "," << pa << "," << helix << "," << web << "," << Num(s.feedMmPerRev)
       << "," << Num(s.speedRpm) << "," << Csv(s.bone) << ","
       << (s.material == 1.0 ? std::string() : Num(s.material)) << ","
       << (s.depthMm >= 1e299 ? std::string() : Num(s.depthMm)) << "," << Num(s.thrustN) << ","
       << (std::isfinite(s.torqueNmm) ? Num(s.torqueNmm) : std::string()) << "," << Csv(r.source)
       << "," << Csv(r.note) << "\n";
  }
  return os.str();
}

std::vector<CalibrationSample> SamplesOf(const std::vector<CalibrationRecord>& records) {
  std::vector<CalibrationSample> out;
  out.reserve(records.size());
  for (const auto& r : records)
    out.push_back(r.sample);
  return out;
}

} // namespace bm
