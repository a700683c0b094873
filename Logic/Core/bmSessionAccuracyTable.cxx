// bmSessionAccuracyTable.cxx - see bmSessionAccuracyTable.h.
#include "bmSessionAccuracyTable.h"

#include <cstdlib>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include "bmCsv.h"
#include "bmRegularFile.h"
#include "bmResources.h"

namespace bm {

namespace {

const char* const kColumns[] = {"scene",
                                "voxmap",
                                "shell",
                                "voxel_mm",
                                "view",
                                "p99_ms",
                                "removed_mm3",
                                "face_depth_mm",
                                "face_angle_deg",
                                "seating",
                                "removed_error_pct",
                                "face_depth_error_mm",
                                "face_error_deg",
                                "seating_error_pct",
                                "reference_voxmap",
                                "reference_shell",
                                "trial_s",
                                "machine",
                                "date"};

/// A table is a few dozen lines; a larger file is not one.
constexpr uint64_t kMaxBytes = uint64_t(16) << 20;

} // namespace

std::string SessionAccuracyCsvHeader() {
  return CsvHeader(kColumns);
}

std::string SessionAccuracyCsvRecord(const SessionAccuracyRow& r) {
  std::ostringstream os;
  os << std::setprecision(9) << CsvQuoted(r.scene) << "," << r.voxmap << "," << r.shell << ","
     << r.voxelMm << "," << int(r.view) << "," << r.p99Ms << "," << r.removedMm3 << ","
     << r.faceDepthMm << "," << r.faceAngleDeg << "," << r.seating << "," << r.removedErrorPct
     << "," << r.faceDepthErrorMm << "," << r.faceErrorDeg << "," << r.seatingErrorPct << ","
     << r.referenceVoxmap << "," << r.referenceShell << "," << r.trialS << ","
     << CsvQuoted(r.machine) << "," << r.date;
  return os.str();
}

std::vector<SessionAccuracyRow> ParseSessionAccuracyCsv(const std::string& text,
                                                        const std::string& source) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line))
    throw std::runtime_error(source + ": empty session accuracy table");
  const std::vector<std::string> header = SplitCsvRecord(line, source + ":1");
  std::map<std::string, size_t> at;
  for (size_t i = 0; i < header.size(); ++i)
    at[header[i]] = i;
  for (const char* c : kColumns)
    if (!at.count(c))
      throw std::runtime_error(source + ": no column '" + c + "'");
  std::vector<SessionAccuracyRow> rows;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos)
      continue;
    const std::string where = source + ":" + std::to_string(n);
    const std::vector<std::string> f = SplitCsvRecord(line, where);
    if (f.size() < header.size())
      throw std::runtime_error(where + ": " + std::to_string(f.size()) + " fields, expected " +
                               std::to_string(header.size()));
    auto text = [&](const char* c) { return f[at[c]]; };
    auto number = [&](const char* c) {
      const std::vector<double> v = ParseCsvNumbers(f[at[c]], where + ", column " + c);
      return v.at(0);
    };
    SessionAccuracyRow r;
    r.scene = text("scene");
    r.voxmap = int(number("voxmap"));
    r.shell = int(number("shell"));
    r.voxelMm = number("voxel_mm");
    r.view = number("view") != 0;
    r.p99Ms = number("p99_ms");
    r.removedMm3 = number("removed_mm3");
    r.faceDepthMm = number("face_depth_mm");
    r.faceAngleDeg = number("face_angle_deg");
    r.seating = number("seating");
    r.removedErrorPct = number("removed_error_pct");
    r.faceDepthErrorMm = number("face_depth_error_mm");
    r.faceErrorDeg = number("face_error_deg");
    r.seatingErrorPct = number("seating_error_pct");
    r.referenceVoxmap = int(number("reference_voxmap"));
    r.referenceShell = int(number("reference_shell"));
    r.trialS = number("trial_s");
    r.machine = text("machine");
    r.date = text("date");
    rows.push_back(r);
  }
  return rows;
}

std::string DefaultSessionAccuracyPath() {
  if (const char* env = std::getenv("BM_SESSION_ACCURACY_CSV"); env && *env)
    return env;
  return ResourcePath("Benchmark/session_accuracy.csv").string();
}

std::vector<SessionAccuracyRow> LoadDefaultSessionAccuracy(std::string* error) {
  return LoadOptionalTable<std::vector<SessionAccuracyRow>>(DefaultSessionAccuracyPath(), kMaxBytes,
                                                            "session accuracy table",
                                                            ParseSessionAccuracyCsv, error);
}

std::string AccuracyBought(const std::vector<SessionAccuracyRow>& rows, const std::string& scene,
                           int voxmap) {
  for (const SessionAccuracyRow& r : rows)
    if (r.scene == scene && r.voxmap == voxmap) {
      std::ostringstream s;
      s << std::fixed << std::setprecision(2) << "its result against the converged reference "
        << "(voxmap " << r.referenceVoxmap << "): removed volume " << std::showpos
        << std::setprecision(1) << r.removedErrorPct << " %, the face's depth "
        << std::setprecision(2) << r.faceDepthErrorMm << " mm" << std::noshowpos
        << " and orientation " << r.faceErrorDeg << " deg, seating " << std::showpos
        << std::setprecision(1) << r.seatingErrorPct << " points" << std::noshowpos << " ("
        << std::setprecision(3) << r.voxelMm << " mm voxels; " << r.machine << ", " << r.date
        << ")";
      return s.str();
    }
  return "";
}

} // namespace bm
