// bm::BenchCsv and bm::ParseBenchCsv: the benchmark table written and read back by the one reader
// that bmsim bench --replot and the panel's expected-cost table (bmBenchmarkTable.h) share.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "bmBenchmark.h"

namespace {

std::string Error(const std::string& text) {
  try {
    bm::ParseBenchCsv(text, "t.csv");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(BenchCsv, WrittenCellsReadBackFieldByField) {
  bm::BenchCell a;
  a.method = bm::Method::Zheng;
  a.backend = "opencl";
  a.shell = 512;
  a.voxmap = 256;
  a.engine = "opencl/zheng";
  a.elements = 123456;
  a.frames = 1000;
  a.medianMs = 0.25;
  a.p99Ms = 0.5;
  a.maxMs = 1.25;
  a.thrustN = 10.5;
  a.torqueNmm = 12.75;
  a.forceError = 0.0015;
  a.peakMemoryMb = 64;
  a.coefficients = "drilling-bovine-orelaja2020";
  a.calibrated = true;
  bm::BenchCell b;
  b.shell = 128;
  b.voxmap = 128;
  b.backend = "cpu";
  b.status = "failed: timed out";
  const std::vector<bm::BenchCell> cells = bm::ParseBenchCsv(bm::BenchCsv({a, b}));
  ASSERT_EQ(cells.size(), 2u);
  EXPECT_EQ(cells[0].method, bm::Method::Zheng);
  EXPECT_EQ(cells[0].backend, "opencl");
  EXPECT_EQ(cells[0].engine, "opencl/zheng");
  EXPECT_EQ(cells[0].shell, 512);
  EXPECT_EQ(cells[0].voxmap, 256);
  EXPECT_EQ(cells[0].elements, 123456);
  EXPECT_EQ(cells[0].frames, 1000);
  EXPECT_DOUBLE_EQ(cells[0].medianMs, 0.25);
  EXPECT_DOUBLE_EQ(cells[0].p99Ms, 0.5);
  EXPECT_DOUBLE_EQ(cells[0].maxMs, 1.25);
  EXPECT_DOUBLE_EQ(cells[0].thrustN, 10.5);
  EXPECT_DOUBLE_EQ(cells[0].torqueNmm, 12.75);
  EXPECT_DOUBLE_EQ(cells[0].forceError, 0.0015);
  EXPECT_DOUBLE_EQ(cells[0].peakMemoryMb, 64);
  EXPECT_EQ(cells[0].coefficients, "drilling-bovine-orelaja2020");
  EXPECT_TRUE(cells[0].calibrated);
  EXPECT_EQ(cells[1].status, "failed: timed out");
  EXPECT_EQ(cells[1].method, bm::Method::Lazar);
  EXPECT_FALSE(cells[1].calibrated);
  // The printed table names the cells' coefficient set.
  EXPECT_NE(bm::BenchTable(cells, bm::Method::Zheng, "t", {512}, {256})
                .find("Coefficients: drilling-bovine-orelaja2020 (calibrated)"),
            std::string::npos);
  EXPECT_NE(Error("method,backend,shell,voxmap,status,median_ms,p99_ms,force_error,calibrated\n"
                  "lazar,cpu,128,64,ok,0.1,0.2,0.003,yes\n")
                .find("column 'calibrated' is not true or false: 'yes'"),
            std::string::npos);
}

TEST(BenchCsv, ATableWithOnlyTheNamedColumnsReads) {
  const auto cells =
      bm::ParseBenchCsv("voxmap,shell,method,backend,status,median_ms,p99_ms,force_error,extra\n"
                        "64,128,lazar,cpu,ok,0.1,0.2,0.003,x\n");
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_EQ(cells[0].shell, 128);
  EXPECT_EQ(cells[0].voxmap, 64);
  EXPECT_DOUBLE_EQ(cells[0].forceError, 0.003);
}

TEST(BenchCsv, BadTablesAreRefusedNamingLineAndColumn) {
  const std::string header = "method,backend,shell,voxmap,status,median_ms,p99_ms,force_error\n";
  EXPECT_EQ(Error(""), "the benchmark table 't.csv' is empty");
  EXPECT_EQ(Error("method,backend\n"), "the benchmark table 't.csv' has no column 'shell'");
  EXPECT_EQ(Error(header + "lazar,cpu,128,128,ok,fast,1,0\n"),
            "t.csv:2: column 'median_ms' is not a number: 'fast'");
  EXPECT_EQ(Error(header + "lazar,cpu,128,128,ok,1,inf,0\n"),
            "t.csv:2: column 'p99_ms' is not a number: 'inf'");
  EXPECT_EQ(Error(header + "lazar,cpu\n"), "t.csv:2: 2 fields, the header has 8");
  // Resolutions are whole numbers of cells in 8..4096 (a bench --replot of such a table failed
  // only when drawing, after writing its tables).
  EXPECT_EQ(Error(header + "lazar,cpu,128.5,128,ok,1,1,0\n"),
            "t.csv:2: column 'shell' is not a resolution in 8..4096: '128.5'");
  EXPECT_EQ(Error(header + "lazar,cpu,128,1e300,ok,1,1,0\n"),
            "t.csv:2: column 'voxmap' is not a resolution in 8..4096: '1e300'");
  EXPECT_NE(Error(header + "kim,cpu,128,128,ok,1,1,0\n").find("t.csv:2: column 'method': "),
            std::string::npos);
}

} // namespace
