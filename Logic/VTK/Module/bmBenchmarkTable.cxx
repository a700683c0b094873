// bmBenchmarkTable.cxx - see bmBenchmarkTable.h.
#include "bmBenchmarkTable.h"

#include "bmRegularFile.h"

#include <charconv>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "bmBenchmark.h"
#include "bmResources.h"

namespace bm {

namespace {
/// Largest benchmark table read, bytes (the shipped one is a few KiB).
constexpr uint64_t kMaxTableBytes = uint64_t(64) << 20;
} // namespace

BenchmarkTable::BenchmarkTable() = default;
BenchmarkTable::~BenchmarkTable() = default;
BenchmarkTable::BenchmarkTable(const BenchmarkTable&) = default;
BenchmarkTable::BenchmarkTable(BenchmarkTable&&) noexcept = default;
BenchmarkTable& BenchmarkTable::operator=(const BenchmarkTable&) = default;
BenchmarkTable& BenchmarkTable::operator=(BenchmarkTable&&) noexcept = default;

const std::vector<BenchCell>& BenchmarkTable::Cells() const {
  return Cells_;
}

std::string BenchmarkTable::DefaultPath() {
  if (const char* env = std::getenv("BM_BENCHMARK_CSV"); env && *env)
    return env;
  return ResourcePath("Benchmark/bench.csv").string();
}

BenchmarkTable BenchmarkTable::Load(const std::string& path) {
  // A FIFO, /dev/zero or a /proc file named as the table would block or never end.
  const std::string text = ReadRegularFile(path, kMaxTableBytes, "the benchmark table");
  BenchmarkTable table;
  for (const BenchCell& c : ParseBenchCsv(text, path)) {
    if (c.status != "ok")
      continue;
    if (c.shell <= 0 || c.voxmap <= 0)
      throw std::runtime_error("the benchmark table '" + path + "': " + ToString(c.method) + "/" +
                               c.backend + ": resolutions must be positive");
    table.Cells_.push_back(c);
  }
  if (table.Cells_.empty())
    throw std::runtime_error("the benchmark table '" + path + "' has no measured (ok) row");
  return table;
}

const BenchCell* BenchmarkTable::Nearest(const std::string& method, const std::string& backend,
                                         int shell, int voxmap) const {
  if (shell <= 0 || voxmap <= 0)
    return nullptr;
  const BenchCell* best = nullptr;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (const BenchCell& c : Cells_) {
    if (ToString(c.method) != method || c.backend != backend)
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
