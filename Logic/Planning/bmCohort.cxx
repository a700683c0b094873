#include "bmCohort.h"

#include "bmCsv.h"
#include "bmJson.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace bm {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool GoodId(const std::string& id) {
  return !id.empty() && id.size() <= 128 && id != "." && id != ".." &&
         std::all_of(id.begin(), id.end(), [](char ch) {
           return std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' ||
                  ch == '-';
         });
}

double Number(const nlohmann::json& o, const char* key) {
  const auto it = o.find(key);
  return it != o.end() && it->is_number() ? it->get<double>() : kNaN;
}

std::string Cell(double v) {
  if (!std::isfinite(v))
    return "";
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

} // namespace

std::vector<CohortCase> ReadCohortCases(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read the case list " + path);
  std::string line;
  int number = 0;
  std::map<std::string, size_t> column;
  std::vector<CohortCase> cases;
  std::set<std::string> ids;
  const fs::path base = fs::absolute(path).parent_path();
  while (std::getline(in, line)) {
    ++number;
    const std::string where = path + ":" + std::to_string(number);
    if (line.find_first_not_of(" \t\r") == std::string::npos)
      continue;
    const std::vector<std::string> f = SplitCsvRecord(line, where);
    if (column.empty()) {
      for (size_t i = 0; i < f.size(); ++i)
        column[f[i]] = i;
      if (!column.count("id") || !column.count("ct"))
        throw std::runtime_error(where + ": the header must name the columns id and ct (and "
                                         "optionally side)");
      continue;
    }
    const auto get = [&](const char* name) {
      const auto it = column.find(name);
      return it != column.end() && it->second < f.size() ? f[it->second] : std::string();
    };
    CohortCase c{get("id"), get("ct"), get("side")};
    if (!GoodId(c.id))
      throw std::runtime_error(where + ": case ID '" + c.id +
                               "' must be letters, digits, '.', '_' or '-'");
    if (!ids.insert(c.id).second)
      throw std::runtime_error(where + ": case ID '" + c.id + "' is repeated");
    if (c.ct.empty())
      throw std::runtime_error(where + ": case " + c.id + " names no CT");
    if (c.side != "" && c.side != "left" && c.side != "right")
      throw std::runtime_error(where + ": case " + c.id + "'s side '" + c.side +
                               "' is not left, right or empty");
    if (c.ct.rfind("pacs://", 0) != 0 && fs::path(c.ct).is_relative())
      c.ct = (base / c.ct).lexically_normal().string();
    cases.push_back(c);
  }
  if (cases.empty())
    throw std::runtime_error("the case list " + path + " holds no case");
  return cases;
}

fs::path CohortCaseFolder(const fs::path& dir, const CohortCase& c) {
  return dir / "cases" / c.id;
}
fs::path CohortCaseLog(const fs::path& dir, const CohortCase& c) {
  return dir / "cases" / (c.id + ".log");
}
fs::path CohortCaseFailure(const fs::path& dir, const CohortCase& c) {
  return dir / "cases" / (c.id + ".failed");
}
bool CohortCaseDone(const fs::path& dir, const CohortCase& c) {
  return fs::is_regular_file(CohortCaseFolder(dir, c) / "plan_report.json");
}

CohortRow CohortRowFor(const fs::path& dir, const CohortCase& c) {
  CohortRow r{c, "pending", "", kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, ""};
  if (!CohortCaseDone(dir, c)) {
    std::ifstream f(CohortCaseFailure(dir, c));
    if (f) {
      r.status = "failed";
      std::getline(f, r.reason, '\0');
      while (!r.reason.empty() && (r.reason.back() == '\n' || r.reason.back() == '\r'))
        r.reason.pop_back();
    }
    return r;
  }
  const fs::path report = CohortCaseFolder(dir, c) / "plan_report.json";
  std::ifstream in(report);
  nlohmann::json j;
  try {
    j = ParseJson(in, report.string());
  } catch (const std::exception& e) {
    r.status = "failed";
    r.reason = "the plan report cannot be read: " + std::string(e.what());
    return r;
  }
  r.status = j.value("status", std::string("failed"));
  if (r.status != "planned") {
    r.reason = j.value("message", std::string());
    return r;
  }
  const nlohmann::json& m = j.value("measurements", nlohmann::json::object());
  const nlohmann::json& p = j.value("plan", nlohmann::json::object());
  const nlohmann::json& l = j.value("landmarks", nlohmann::json::object());
  r.side = l.value("side", std::string());
  r.version3dDeg = Number(m, "version_3d_deg");
  r.friedmanVersionDeg = Number(m, "friedman_version_deg");
  r.inclinationDeg = Number(m, "inclination_deg");
  r.heightMm = Number(m, "glenoid_height_mm");
  r.widthMm = Number(m, "glenoid_width_mm");
  r.correctionDeg = Number(p, "correction_deg");
  if (const auto w = p.find("warnings"); w != p.end() && w->is_array())
    for (const auto& s : *w)
      if (s.is_string())
        r.reason += (r.reason.empty() ? "" : "; ") + s.get<std::string>();
  return r;
}

std::string CohortTableCsv(const std::vector<CohortRow>& rows) {
  static const char* const kColumns[] = {"id",
                                         "ct",
                                         "side",
                                         "status",
                                         "version_3d_deg",
                                         "friedman_version_deg",
                                         "inclination_deg",
                                         "glenoid_height_mm",
                                         "glenoid_width_mm",
                                         "correction_deg",
                                         "reason"};
  std::string csv = CsvHeader(kColumns) + "\n";
  for (const CohortRow& r : rows)
    csv += CsvQuoted(r.c.id) + "," + CsvQuoted(r.c.ct) + "," + r.side + "," + r.status + "," +
           Cell(r.version3dDeg) + "," + Cell(r.friedmanVersionDeg) + "," + Cell(r.inclinationDeg) +
           "," + Cell(r.heightMm) + "," + Cell(r.widthMm) + "," + Cell(r.correctionDeg) + "," +
           CsvQuoted(r.reason) + "\n";
  return csv;
}

} // namespace bm
