// bmBenchmarkTable.cxx - see bmBenchmarkTable.h.
#include "bmBenchmarkTable.h"

#include <charconv>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "bmResources.h"

namespace bm {

namespace {
std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ','))
    out.push_back(field);
  if (!line.empty() && line.back() == ',')
    out.emplace_back();
  return out;
}

double ParseNumber(const std::string& text, const std::string& path, int line,
                   const std::string& column) {
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value))
    throw std::runtime_error(path + ":" + std::to_string(line) + ": column '" + column +
                             "' is not a number: '" + text + "'");
  return value;
}
} // namespace

std::string BenchmarkTable::DefaultPath() {
  if (const char* env = std::getenv("BM_BENCHMARK_CSV"); env && *env)
    return env;
  return ResourcePath("Benchmark/bench.csv").string();
}

BenchmarkTable BenchmarkTable::Load(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read the benchmark table '" + path + "'");
  std::string line;
  if (!std::getline(in, line))
    throw std::runtime_error("the benchmark table '" + path + "' is empty");
  const std::vector<std::string> header = SplitCsv(line);
  std::map<std::string, size_t> column;
  for (size_t i = 0; i < header.size(); ++i)
    column[header[i]] = i;
  const char* const needed[] = {"method", "backend",   "shell",  "voxmap",
                                "status", "median_ms", "p99_ms", "force_error"};
  for (const char* name : needed)
    if (!column.count(name))
      throw std::runtime_error("the benchmark table '" + path + "' has no column '" + name + "'");

  BenchmarkTable table;
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty())
      continue;
    const std::vector<std::string> f = SplitCsv(line);
    if (f.size() < header.size())
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": " +
                               std::to_string(f.size()) + " fields, the header has " +
                               std::to_string(header.size()));
    if (f[column["status"]] != "ok")
      continue;
    BenchmarkCell c;
    c.method = f[column["method"]];
    c.backend = f[column["backend"]];
    c.shell = int(ParseNumber(f[column["shell"]], path, lineNo, "shell"));
    c.voxmap = int(ParseNumber(f[column["voxmap"]], path, lineNo, "voxmap"));
    c.medianMs = ParseNumber(f[column["median_ms"]], path, lineNo, "median_ms");
    c.p99Ms = ParseNumber(f[column["p99_ms"]], path, lineNo, "p99_ms");
    c.forceError = ParseNumber(f[column["force_error"]], path, lineNo, "force_error");
    if (c.shell <= 0 || c.voxmap <= 0)
      throw std::runtime_error(path + ":" + std::to_string(lineNo) +
                               ": resolutions must be positive");
    table.Cells_.push_back(c);
  }
  if (table.Cells_.empty())
    throw std::runtime_error("the benchmark table '" + path + "' has no measured (ok) row");
  return table;
}

const BenchmarkCell* BenchmarkTable::Nearest(const std::string& method, const std::string& backend,
                                             int shell, int voxmap) const {
  if (shell <= 0 || voxmap <= 0)
    return nullptr;
  const BenchmarkCell* best = nullptr;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (const BenchmarkCell& c : Cells_) {
    if (c.method != method || c.backend != backend)
      continue;
    const double ds = std::log2(double(c.shell) / shell);
    const double dv = std::log2(double(c.voxmap) / voxmap);
    const double d = ds * ds + dv * dv;
    const bool finer = best && (c.shell + c.voxmap > best->shell + best->voxmap);
    if (d < bestDistance - 1e-12 || (std::abs(d - bestDistance) <= 1e-12 && finer)) {
      best = &c;
      bestDistance = d;
    }
  }
  return best;
}

} // namespace bm
