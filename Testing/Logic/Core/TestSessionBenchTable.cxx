// The session benchmark table (bmSessionBenchTable.h): what `bmsim bench --session` writes reads
// back field for field, and a damaged table is refused naming the line and the column.
#include "bmSessionBenchTable.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

TEST(SessionBenchTable, RecordsReadBackFieldForField) {
  bm::SessionBenchRow a;
  a.scene = "glenoid";
  a.voxmap = 96;
  a.shell = 170;
  a.threads = 2;
  a.path = "incremental";
  a.view = true;
  a.run = 3;
  a.frames = 10000;
  a.p50Ms = 0.683154;
  a.p99Ms = 1.49816;
  a.maxMs = 7.94203;
  a.over = 1116;
  a.overrunPauses = 180;
  a.seconds = 10;
  a.machine = "AMD EPYC, 2 logical cores";
  a.date = "2026-11-26";
  bm::SessionBenchRow b = a;
  b.path = "full";
  b.view = false;
  const auto rows =
      bm::ParseSessionBenchCsv(bm::SessionBenchCsvHeader() + "\n" + bm::SessionBenchCsvRecord(a) +
                                   "\n" + bm::SessionBenchCsvRecord(b) + "\n",
                               "written");
  ASSERT_EQ(rows.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const bm::SessionBenchRow& w = i == 0 ? a : b;
    const bm::SessionBenchRow& r = rows[size_t(i)];
    EXPECT_EQ(r.scene, w.scene);
    EXPECT_EQ(r.voxmap, w.voxmap);
    EXPECT_EQ(r.shell, w.shell);
    EXPECT_EQ(r.threads, w.threads);
    EXPECT_EQ(r.path, w.path);
    EXPECT_EQ(r.view, w.view);
    EXPECT_EQ(r.run, w.run);
    EXPECT_EQ(r.frames, w.frames);
    EXPECT_DOUBLE_EQ(r.p50Ms, w.p50Ms);
    EXPECT_DOUBLE_EQ(r.p99Ms, w.p99Ms);
    EXPECT_DOUBLE_EQ(r.maxMs, w.maxMs);
    EXPECT_EQ(r.over, w.over);
    EXPECT_EQ(r.overrunPauses, w.overrunPauses);
    EXPECT_DOUBLE_EQ(r.seconds, w.seconds);
    EXPECT_EQ(r.machine, w.machine);
    EXPECT_EQ(r.date, w.date);
  }
  // The cell with the view and the one without are told apart.
  EXPECT_TRUE(bm::NearestSessionCell(rows, "glenoid", 96, 170, true, "incremental"));
  EXPECT_FALSE(bm::NearestSessionCell(rows, "glenoid", 96, 170, false, "incremental"));
  EXPECT_TRUE(bm::NearestSessionCell(rows, "glenoid", 96, 170, false, "full"));
}

TEST(SessionBenchTable, DamagedTablesAreRefusedByLineAndColumn) {
  const std::string header = bm::SessionBenchCsvHeader() + "\n";
  auto refused = [](const std::string& text, const std::string& what) {
    try {
      bm::ParseSessionBenchCsv(text, "t.csv");
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted: " << text;
  };
  refused("", "is empty");
  refused("scene,voxmap\n", "has no column 'shell'");
  refused(header + "glenoid,96,170,2,incremental,1,1,10\n", "t.csv:2: 8 fields");
  refused(header + "glenoid,96,170,2,incremental,2,1,10,1,1,1,0,0,10,m,d,cpu\n",
          "t.csv:2: column 'view'");
  refused(header + "glenoid,96,170,2,incremental,1,1,10,nan,1,1,0,0,10,m,d,cpu\n",
          "column 'p50_ms'");
  refused(header + "glenoid,96,170,2,incremental,1,1,10,1,1,1,0,0,10,m,d,gpu\n",
          "column 'backend' must be cpu or opencl");
}

// Tables from before the backend column are the CPU backend's; the OpenCL backend's rows are
// never taken for the CPU's cell.
TEST(SessionBenchTable, TheBackendColumnIsOptionalAndKeepsBackendsApart) {
  std::string old = bm::SessionBenchCsvHeader();
  old = old.substr(0, old.rfind(",backend")) + "\n";
  const auto rows = bm::ParseSessionBenchCsv(
      old + "glenoid,96,170,1,incremental,0,1,10,0.2,0.5,1,0,0,10,m,d\n", "old.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].backend, "cpu");
  bm::SessionBenchRow gpu = rows[0];
  gpu.backend = "opencl";
  gpu.voxmap = 192;
  gpu.shell = 340;
  const auto both = bm::ParseSessionBenchCsv(
      bm::SessionBenchCsvHeader() + "\n" + bm::SessionBenchCsvRecord(gpu) + "\n", "new.csv");
  ASSERT_EQ(both.size(), 1u);
  EXPECT_EQ(both[0].backend, "opencl");
  EXPECT_FALSE(bm::NearestSessionCell(both, "glenoid", 192, 340, false));
  EXPECT_TRUE(
      bm::NearestSessionCell(both, "glenoid", 192, 340, false, "incremental", 1.5, 0, "opencl"));
}
