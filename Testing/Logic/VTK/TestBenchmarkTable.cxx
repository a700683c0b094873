// bm::BenchmarkTable: reads the measured bench.csv, finds the nearest measured cell, and refuses
// malformed tables naming the problem.
#include "bmBenchmarkTable.h"

#include "bmBenchmark.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace fs = std::filesystem;

namespace {
const char* const kHeader = "method,backend,shell,voxmap,status,median_ms,p99_ms,force_error\n";

fs::path WriteTable(const std::string& name, const std::string& text) {
  const fs::path path = fs::temp_directory_path() / ("bm-bench-" + name + ".csv");
  std::ofstream(path) << text;
  return path;
}

std::string LoadError(const std::string& text) {
  const fs::path path = WriteTable("bad", text);
  try {
    bm::BenchmarkTable::Load(path.string());
  } catch (const std::runtime_error& e) {
    fs::remove(path);
    return e.what();
  }
  fs::remove(path);
  return "";
}
} // namespace

TEST(BenchmarkTable, InstalledTableFindsEachMeasuredCell) {
  // Whatever the figures (bench.csv is re-measured now and then): the installed table reads,
  // covers both methods on the CPU, and a measured resolution finds its own cell.
  unsetenv("BM_BENCHMARK_CSV");
  const bm::BenchmarkTable table = bm::BenchmarkTable::Load(bm::BenchmarkTable::DefaultPath());
  ASSERT_FALSE(table.Cells().empty());
  EXPECT_NE(table.Nearest("lazar", "cpu", 256, 256), nullptr);
  EXPECT_NE(table.Nearest("zheng", "cpu", 256, 256), nullptr);
  for (const bm::BenchCell& c : table.Cells()) {
    EXPECT_EQ(table.Nearest(bm::ToString(c.method), c.backend, c.shell, c.voxmap), &c)
        << bm::ToString(c.method) << "/" << c.backend << " " << c.shell << "/" << c.voxmap;
    EXPECT_GT(c.medianMs, 0);
    EXPECT_GE(c.p99Ms, c.medianMs);
    EXPECT_GE(c.forceError, 0);
  }
}

TEST(BenchmarkTable, EnvironmentChoosesTheTable) {
  setenv("BM_BENCHMARK_CSV", "/somewhere/else.csv", 1);
  EXPECT_EQ(bm::BenchmarkTable::DefaultPath(), "/somewhere/else.csv");
  unsetenv("BM_BENCHMARK_CSV");
  EXPECT_NE(bm::BenchmarkTable::DefaultPath(), "/somewhere/else.csv");
}

TEST(BenchmarkTable, NearestInLogResolution) {
  const fs::path path =
      WriteTable("nearest", std::string(kHeader) + "lazar,cpu,128,128,ok,1,2,0.1\n"
                                                   "lazar,cpu,512,128,ok,3,4,0.2\n"
                                                   "lazar,cpu,512,512,ok,5,6,0.3\n"
                                                   "lazar,cpu,2048,2048,failed,7,8,0.4\n"
                                                   "zheng,cpu,128,128,ok,9,10,0.5\n"
                                                   "lazar,opencl,128,128,ok,11,12,0.6\n");
  const bm::BenchmarkTable table = bm::BenchmarkTable::Load(path.string());
  fs::remove(path);
  EXPECT_EQ(table.Cells().size(), 5u); // the failed row is skipped
  // 200 is nearer 128 than 512 in log2 (0.64 against 1.36).
  EXPECT_EQ(table.Nearest("lazar", "cpu", 200, 100)->medianMs, 1);
  EXPECT_EQ(table.Nearest("lazar", "cpu", 400, 150)->medianMs, 3);
  // The failed 2048 cell is not measured: 4096 / 4096 falls back to 512 / 512.
  EXPECT_EQ(table.Nearest("lazar", "cpu", 4096, 4096)->medianMs, 5);
  // Equidistant (256 between 128 and 512): the finer cell.
  EXPECT_EQ(table.Nearest("lazar", "cpu", 256, 128)->medianMs, 3);
  EXPECT_EQ(table.Nearest("zheng", "cpu", 2048, 2048)->medianMs, 9);
  EXPECT_EQ(table.Nearest("lazar", "opencl", 64, 64)->medianMs, 11);
  EXPECT_EQ(table.Nearest("zheng", "opencl", 128, 128), nullptr);
  EXPECT_EQ(table.Nearest("lazar", "cpu", 0, 128), nullptr);
}

TEST(BenchmarkTable, BadTablesAreRefusedNamingTheProblem) {
  EXPECT_NE(LoadError("").find("is empty"), std::string::npos);
  EXPECT_NE(LoadError("method,backend,shell,voxmap,status,median_ms,p99_ms\n")
                .find("no column 'force_error'"),
            std::string::npos);
  EXPECT_NE(LoadError(std::string(kHeader) + "lazar,cpu,128,128,ok,fast,2,0.1\n")
                .find(":2: column 'median_ms' is not a number: 'fast'"),
            std::string::npos);
  EXPECT_NE(LoadError(std::string(kHeader) + "lazar,cpu,128\n").find(":2: 3 fields"),
            std::string::npos);
  EXPECT_NE(LoadError(std::string(kHeader) + "lazar,cpu,128,128,failed,1,2,0.1\n")
                .find("no measured (ok) row"),
            std::string::npos);
  EXPECT_THROW(bm::BenchmarkTable::Load("/nonexistent/bench.csv"), std::runtime_error);
}
