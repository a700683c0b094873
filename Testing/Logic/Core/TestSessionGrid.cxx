// The grid a session chooses (bmSessionGrid.h): this machine's measured limit is the finest
// voxmap whose worst p99 holds the period, with the threads that measured best there; the scene
// is capped by it, its shell scaled alike; and the nearest measured cell can be asked for one
// thread count.
#include "bmSessionGrid.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace {

bm::SessionBenchRow Row(int voxmap, int threads, double p99, bool view = false,
                        const std::string& path = "incremental") {
  bm::SessionBenchRow r;
  r.scene = "glenoid";
  r.voxmap = voxmap;
  r.shell = int(voxmap * 340 / 192);
  r.threads = threads;
  r.path = path;
  r.view = view;
  r.run = 1;
  r.frames = 5000;
  r.p50Ms = p99 / 2;
  r.p99Ms = p99;
  r.maxMs = p99 * 4;
  r.seconds = 5;
  r.machine = "test machine";
  r.date = "2026-11-26";
  return r;
}

} // namespace

TEST(SessionGrid, TheFinestVoxmapThatHoldsThePeriodWithItsBestThreads) {
  const std::vector<bm::SessionBenchRow> rows = {
      Row(64, 2, 0.60), Row(64, 1, 0.40), Row(96, 2, 1.20), Row(96, 1, 0.90), Row(96, 1, 0.95),
      Row(128, 1, 2.30), Row(128, 2, 2.1),
      // Other paths, views and scenes do not count.
      Row(192, 1, 0.5, false, "full"), Row(192, 1, 0.5, true)};
  auto l = bm::MeasuredSessionLimit(rows, "glenoid", false, 1.0);
  ASSERT_TRUE(l);
  EXPECT_EQ(l->voxmap, 96);
  EXPECT_EQ(l->threads, 1);
  EXPECT_DOUBLE_EQ(l->p99Ms, 0.95); // the worst of the cell's runs
  EXPECT_TRUE(l->holds);
  // A longer period holds at 128 with two threads (2.1 < 2.3).
  l = bm::MeasuredSessionLimit(rows, "glenoid", false, 2.2);
  ASSERT_TRUE(l);
  EXPECT_EQ(l->voxmap, 128);
  EXPECT_EQ(l->threads, 2);
  // With the view only the 192 row was measured.
  l = bm::MeasuredSessionLimit(rows, "glenoid", true, 1.0);
  ASSERT_TRUE(l);
  EXPECT_EQ(l->voxmap, 192);
  EXPECT_FALSE(bm::MeasuredSessionLimit(rows, "skull", false, 1.0));
}

TEST(SessionGrid, WhenNothingHoldsTheCoarsestIsChosenAndSaidSo) {
  const std::vector<bm::SessionBenchRow> rows = {Row(96, 1, 1.5), Row(64, 1, 1.1),
                                                 Row(128, 2, 2.0)};
  const auto l = bm::MeasuredSessionLimit(rows, "glenoid", false, 1.0);
  ASSERT_TRUE(l);
  EXPECT_EQ(l->voxmap, 64);
  EXPECT_FALSE(l->holds);
  const bm::SessionGridPlan plan =
      bm::PlanSessionGrid(bm::Scene::Builtin("glenoid"), rows, false, 1000.0);
  EXPECT_EQ(plan.scene.voxmapResolution, 64);
  EXPECT_NE(plan.reason.find("no measured voxmap holds the rate"), std::string::npos)
      << plan.reason;
}

TEST(SessionGrid, ThePlanCapsTheSceneAndScalesItsShell) {
  const bm::Scene glenoid = bm::Scene::Builtin("glenoid");
  ASSERT_EQ(glenoid.voxmapResolution, 192);
  ASSERT_EQ(glenoid.shellResolution, 340);
  const std::vector<bm::SessionBenchRow> rows = {Row(96, 1, 0.9), Row(192, 2, 2.0)};
  bm::SessionGridPlan plan = bm::PlanSessionGrid(glenoid, rows, false, 1000.0);
  EXPECT_EQ(plan.scene.voxmapResolution, 96);
  EXPECT_EQ(plan.scene.shellResolution, 170); // 340 x 96 / 192
  EXPECT_EQ(plan.scene.threads, 1);
  EXPECT_NE(plan.reason.find("voxmap 96 with 1 engine thread has frame p99 0.9 ms"),
            std::string::npos)
      << plan.reason;
  // A limit finer than the scene's never refines it; no measurements keep the scene's.
  const std::vector<bm::SessionBenchRow> fine = {Row(512, 2, 0.5)};
  plan = bm::PlanSessionGrid(glenoid, fine, false, 1000.0);
  EXPECT_EQ(plan.scene.voxmapResolution, 192);
  EXPECT_EQ(plan.scene.shellResolution, 340);
  plan = bm::PlanSessionGrid(glenoid, {}, false, 1000.0);
  EXPECT_EQ(plan.scene.voxmapResolution, 192);
  EXPECT_FALSE(plan.limit);
  EXPECT_NE(plan.reason.find("no session measurements"), std::string::npos) << plan.reason;
}

// The session accuracy table (bmsim bench --session --accuracy): written and read back the same;
// the choice's reason says what the chosen voxmap buys; a damaged table names line and column.
TEST(SessionGrid, TheChoiceSaysWhatAccuracyItBuys) {
  bm::SessionAccuracyRow a;
  a.scene = "glenoid";
  a.voxmap = 96;
  a.shell = 170;
  a.voxelMm = 0.4296875;
  a.p99Ms = 0.9;
  a.removedMm3 = 2140.5;
  a.removedErrorPct = -2.57;
  a.faceDepthErrorMm = -0.031;
  a.faceErrorDeg = 0.37;
  a.seatingErrorPct = 0.25;
  a.referenceVoxmap = 384;
  a.referenceShell = 680;
  a.machine = "CPU, 2 cores";
  a.date = "2026-11-29";
  const std::vector<bm::SessionAccuracyRow> read = bm::ParseSessionAccuracyCsv(
      bm::SessionAccuracyCsvHeader() + "\n" + bm::SessionAccuracyCsvRecord(a) + "\n", "t.csv");
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(bm::SessionAccuracyCsvRecord(read[0]), bm::SessionAccuracyCsvRecord(a));
  EXPECT_EQ(read[0].machine, "CPU, 2 cores");
  EXPECT_EQ(read[0].referenceVoxmap, 384);

  const std::vector<bm::SessionBenchRow> rows = {Row(96, 1, 0.9), Row(192, 2, 2.0)};
  const bm::SessionGridPlan plan =
      bm::PlanSessionGrid(bm::Scene::Builtin("glenoid"), rows, false, 1000.0, read);
  EXPECT_EQ(plan.scene.voxmapResolution, 96);
  EXPECT_NE(plan.reason.find("; its result against the converged reference (voxmap 384): "
                             "removed volume -2.6 %, the face's depth -0.03 mm and orientation "
                             "0.37 deg, seating +0.2 points (0.430 mm voxels"),
            std::string::npos)
      << plan.reason;
  // Another scene's, or another voxmap's, row says nothing.
  EXPECT_EQ(bm::AccuracyBought(read, "skull", 96), "");
  EXPECT_EQ(bm::AccuracyBought(read, "glenoid", 64), "");
  try {
    bm::ParseSessionAccuracyCsv(bm::SessionAccuracyCsvHeader() +
                                    "\nglenoid,96,170,x,0,0,0,0,0,0,0,0,0,0,384,680,1,m,d\n",
                                "t.csv");
    ADD_FAILURE() << "a voxel size that is not a number was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("t.csv:2, column voxel_mm"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(bm::ParseSessionAccuracyCsv("scene,voxmap\nglenoid,96\n", "t.csv"),
               std::runtime_error);
}

TEST(SessionGrid, TheNearestCellForOneThreadCount) {
  const std::vector<bm::SessionBenchRow> rows = {Row(96, 1, 0.9), Row(96, 2, 1.3)};
  auto any = bm::NearestSessionCell(rows, "glenoid", 96, 170, false);
  ASSERT_TRUE(any);
  auto one = bm::NearestSessionCell(rows, "glenoid", 96, 170, false, "incremental", 1.5, 1);
  ASSERT_TRUE(one);
  EXPECT_DOUBLE_EQ(one->p99Ms, 0.9);
  auto two = bm::NearestSessionCell(rows, "glenoid", 96, 170, false, "incremental", 1.5, 2);
  ASSERT_TRUE(two);
  EXPECT_DOUBLE_EQ(two->p99Ms, 1.3);
  EXPECT_FALSE(bm::NearestSessionCell(rows, "glenoid", 96, 170, false, "incremental", 1.5, 4));
}

TEST(SessionGrid, ASmallToolKeepsEightVoxelsAcrossIt) {
  EXPECT_DOUBLE_EQ(bm::ToolVoxelMm(2.0), 0.5);      // the skull scene's 2 mm burr
  EXPECT_DOUBLE_EQ(bm::ToolVoxelMm(18.25), 4.5625); // the 36.5 mm glenoid reamer
}

// The session table named by BM_SESSION_BENCHMARK_CSV (or found in BM_RESOURCE_DIR) is a file a
// user may point anywhere: a FIFO would block the read, /dev/zero never ends, a /proc file may
// block (/proc/kmsg). Each is refused by name, at once.
TEST(SessionGrid, ATableThatIsNotAPlainFileIsRefusedAtOnce) {
  const std::string fifo =
      (std::filesystem::temp_directory_path() / ("bm-table-fifo-" + std::to_string(::getpid())))
          .string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string link = fifo + ".csv";
  std::filesystem::create_symlink("/proc/self/status", link);
  for (const auto& [path, why] : std::vector<std::pair<std::string, std::string>>{
           {fifo, "a FIFO"}, {"/dev/zero", "a device"}, {link, "a kernel interface file"}}) {
    ::setenv("BM_SESSION_BENCHMARK_CSV", path.c_str(), 1);
    std::string error;
    const auto rows = bm::LoadDefaultSessionTable(&error);
    EXPECT_TRUE(rows.empty()) << path;
    EXPECT_NE(error.find(why), std::string::npos) << path << ": " << error;
  }
  ::unsetenv("BM_SESSION_BENCHMARK_CSV");
  std::filesystem::remove(fifo);
  std::filesystem::remove(link);
}
