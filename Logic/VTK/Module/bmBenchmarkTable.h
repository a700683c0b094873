// bmBenchmarkTable.h - the measured cost and accuracy of the engine per resolution, as `bmsim
// bench` wrote them (Resources/Benchmark/bench.csv), for showing the expected frame time and force
// error of a chosen resolution before running it.
//
// The CSV has a header row naming its columns; the ones read are method, backend, shell, voxmap,
// status, median_ms, p99_ms and force_error (other columns are ignored, rows whose status is not
// "ok" are skipped). The figures are those of the benchmark's case (the reference drill in a
// cortical block), measured on the machine named in Resources/Benchmark/table1.md: they scale with
// the number of shell elements in contact, so they are a guide for other tools and scenes.
//
// Units: ms; force error as a fraction (0.01 = 1 %) of the quadrature reference.
#pragma once

#include <string>
#include <vector>

namespace bm {

/// One measured cell (bmBenchmark.h; declared here so that the plugin, which does not see BMCore's
/// headers, can hold a table: users of the cells include bmBenchmark.h).
struct BenchCell;

class BenchmarkTable {
public:
  BenchmarkTable();
  ~BenchmarkTable();
  BenchmarkTable(const BenchmarkTable&);
  BenchmarkTable(BenchmarkTable&&) noexcept;
  BenchmarkTable& operator=(const BenchmarkTable&);
  BenchmarkTable& operator=(BenchmarkTable&&) noexcept;

  /// Reads a bench.csv through bm::ParseBenchCsv (bmBenchmark.h, the one reader of the table).
  /// Throws std::runtime_error naming the file and the problem (unreadable, a missing column, a
  /// malformed number with its line), and when no row has status "ok".
  static BenchmarkTable Load(const std::string& path);
  /// The table to read: $BM_BENCHMARK_CSV when set and not empty (e.g. a machine's own
  /// measurements, or a test's), else Benchmark/bench.csv in the resource folder (bmResources.h:
  /// the source tree's Resources/ in a build tree, <prefix>/share/BoneMachining once installed).
  static std::string DefaultPath();

  /// The measured cells (status "ok" only), in file order.
  const std::vector<BenchCell>& Cells() const;

  /// The measured cell of `method` ("lazar" or "zheng") and `backend` nearest to (shell, voxmap):
  /// the smallest Euclidean distance in (log2 shell, log2 voxmap) (a doubling of either counts 1),
  /// ties to the finer cell. Returns nullptr when the table has no cell of that method and backend
  /// or a resolution is not positive.
  const BenchCell* Nearest(const std::string& method, const std::string& backend, int shell,
                           int voxmap) const;

private:
  std::vector<BenchCell> Cells_;
};

} // namespace bm
