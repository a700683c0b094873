// bmSessionBenchTable.cxx - see bmSessionBenchTable.h.
#include "bmSessionBenchTable.h"

#include "bmCsv.h"
#include "bmResources.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

namespace bm {

namespace {

// The columns a table must have; "backend" after them is written and read when present (tables
// without it were measured on the CPU backend).
const char* const kColumns[] = {
    "scene",  "voxmap", "shell",  "threads", "path",           "view",    "run",     "frames",
    "p50_ms", "p99_ms", "max_ms", "over",    "overrun_pauses", "seconds", "machine", "date"};

} // namespace

std::string SessionBenchCsvHeader() {
  return CsvHeader(kColumns) + ",backend";
}

std::string SessionBenchCsvRecord(const SessionBenchRow& r) {
  std::ostringstream os;
  os.precision(6);
  os << CsvQuoted(r.scene) << "," << r.voxmap << "," << r.shell << "," << r.threads << "," << r.path
     << "," << (r.view ? 1 : 0) << "," << r.run << "," << r.frames << "," << r.p50Ms << ","
     << r.p99Ms << "," << r.maxMs << "," << r.over << "," << r.overrunPauses << "," << r.seconds
     << "," << CsvQuoted(r.machine) << "," << r.date << "," << r.backend;
  return os.str();
}

std::vector<SessionBenchRow> ParseSessionBenchCsv(const std::string& text,
                                                  const std::string& source) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line.empty())
    throw std::runtime_error("the session benchmark table '" + source + "' is empty");
  const std::vector<std::string> header = SplitCsvRecord(line, source);
  std::map<std::string, size_t> column;
  for (size_t i = 0; i < header.size(); ++i)
    column[header[i]] = i;
  for (const char* name : kColumns)
    if (!column.count(name))
      throw std::runtime_error("the session benchmark table '" + source + "' has no column '" +
                               name + "'");
  std::vector<SessionBenchRow> rows;
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty() || line == "\r")
      continue;
    const std::vector<std::string> f = SplitCsvRecord(line, source);
    const std::string at = source + ":" + std::to_string(lineNo) + ": ";
    if (f.size() < header.size())
      throw std::runtime_error(at + std::to_string(f.size()) + " fields, the header has " +
                               std::to_string(header.size()));
    auto text = [&](const char* name) -> const std::string& { return f[column.at(name)]; };
    auto number = [&](const char* name, double lo, double hi) {
      const std::string& t = text(name);
      double v = 0;
      const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
      if (ec != std::errc() || ptr != t.data() + t.size() || !std::isfinite(v) || v < lo || v > hi)
        throw std::runtime_error(at + "column '" + name + "' is not a number in [" +
                                 std::to_string(lo) + ", " + std::to_string(hi) + "]: '" + t + "'");
      return v;
    };
    SessionBenchRow r;
    r.scene = text("scene");
    r.voxmap = int(number("voxmap", 1, 8192));
    r.shell = int(number("shell", 1, 8192));
    r.threads = int(number("threads", 1, 1024));
    r.path = text("path");
    if (r.path != "incremental" && r.path != "full")
      throw std::runtime_error(at + "column 'path' must be incremental or full, not '" + r.path +
                               "'");
    r.view = number("view", 0, 1) != 0;
    r.run = int(number("run", 1, 1e6));
    r.frames = (long long)number("frames", 0, 1e12);
    r.p50Ms = number("p50_ms", 0, 1e9);
    r.p99Ms = number("p99_ms", 0, 1e9);
    r.maxMs = number("max_ms", 0, 1e9);
    r.over = (long long)number("over", 0, 1e12);
    r.overrunPauses = (long long)number("overrun_pauses", 0, 1e12);
    r.seconds = number("seconds", 0, 1e9);
    r.machine = text("machine");
    r.date = text("date");
    if (column.count("backend")) {
      const std::string& backend = text("backend");
      if (backend != "cpu" && backend != "opencl")
        throw std::runtime_error(at + "column 'backend' must be cpu or opencl, not '" + backend +
                                 "'");
      r.backend = backend;
    }
    rows.push_back(std::move(r));
  }
  return rows;
}

std::optional<SessionBenchRow> NearestSessionCell(const std::vector<SessionBenchRow>& rows,
                                                  const std::string& scene, int voxmap, int shell,
                                                  bool view, const std::string& path,
                                                  double maxRatio, int threads,
                                                  const std::string& backend) {
  auto wanted = [&](const SessionBenchRow& r) {
    return r.scene == scene && r.path == path && r.view == view && r.backend == backend &&
           (threads <= 0 || r.threads == threads);
  };
  const SessionBenchRow* best = nullptr;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (const SessionBenchRow& r : rows) {
    if (!wanted(r))
      continue;
    // Voxmap first: it sets the engine's and the contact's work; the shell second.
    const double d = std::abs(std::log(double(r.voxmap) / std::max(voxmap, 1))) * 1000.0 +
                     std::abs(std::log(double(r.shell) / std::max(shell, 1)));
    if (d < bestDistance) {
      bestDistance = d;
      best = &r;
    }
  }
  if (!best ||
      std::abs(std::log(double(best->voxmap) / std::max(voxmap, 1))) > std::log(maxRatio) + 1e-12)
    return std::nullopt;
  SessionBenchRow cell = *best;
  cell.frames = cell.over = cell.overrunPauses = 0;
  cell.seconds = cell.p99Ms = cell.maxMs = 0;
  std::vector<double> p50s;
  for (const SessionBenchRow& r : rows)
    if (wanted(r) && r.voxmap == best->voxmap && r.shell == best->shell &&
        r.threads == best->threads) {
      cell.frames += r.frames;
      cell.over += r.over;
      cell.overrunPauses += r.overrunPauses;
      cell.seconds += r.seconds;
      cell.p99Ms = std::max(cell.p99Ms, r.p99Ms);
      cell.maxMs = std::max(cell.maxMs, r.maxMs);
      p50s.push_back(r.p50Ms);
    }
  std::sort(p50s.begin(), p50s.end());
  cell.p50Ms = p50s[p50s.size() / 2];
  return cell;
}

std::string DefaultSessionBenchPath() {
  if (const char* env = std::getenv("BM_SESSION_BENCHMARK_CSV"); env && *env)
    return env;
  return ResourcePath("Benchmark/session.csv").string();
}

} // namespace bm
