// bmPanelLogic: the panel's labels, tooltips, bone file extension, state words, force scale
// range and expected-cost line, without Qt.
#include "bmPanelLogic.h"

#include "bmHapticSession.h"
#include "bmSessionAccuracyTable.h"
#include "bmSessionBenchTable.h"
#include "vtkBMSessionSource.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace PL = bm::PanelLogic;

TEST(PanelLogic, ParameterLabelsCarryTheUnit) {
  EXPECT_EQ(PL::ParameterLabel("arc_centre_offset_mm"), "Arc centre offset (mm)");
  EXPECT_EQ(PL::ParameterLabel("alpha_deg"), "Alpha (deg)");
  EXPECT_EQ(PL::ParameterLabel("speed_rpm"), "Speed (rpm)");
  EXPECT_EQ(PL::ParameterLabel("lips"), "Lips");
}

TEST(PanelLogic, EachParameterHasItsOwnToolTip) {
  EXPECT_NE(PL::ParameterToolTip("nipple_radius_mm"), PL::ParameterToolTip("lips"));
  EXPECT_NE(PL::ParameterToolTip("nipple_radius_mm").find("mm"), std::string::npos);
  EXPECT_EQ(PL::ParameterToolTip("wobble_mm"), "Tool parameter: Wobble (mm)");
}

// The CT dialog offers every type the import reads: ITK's volumes, DICOM, InVesalius projects and
// VTK images (the .vti a tester could not pick although the import reads it).
TEST(PanelLogic, TheCTFileDialogOffersEveryTypeTheImportReads) {
  const std::string filter = PL::CTFileFilter();
  for (const char* ext : {"*.nrrd", "*.nhdr", "*.mha", "*.mhd", "*.nii", "*.nii.gz", "*.dcm",
                          "*.inv3", "*.vti", "*.vtk"})
    EXPECT_NE(filter.find(ext), std::string::npos) << ext << " missing from " << filter;
  EXPECT_EQ(filter.rfind(";;All files (*)"), filter.size() - std::string(";;All files (*)").size());
}

TEST(PanelLogic, BoneFileGetsAVoxmapExtension) {
  EXPECT_EQ(PL::WithVoxmapExtension("/tmp/cut"), "/tmp/cut.nrrd");
  EXPECT_EQ(PL::WithVoxmapExtension("/tmp/cut", "mha"), "/tmp/cut.mha");
  EXPECT_EQ(PL::WithVoxmapExtension("/tmp/cut.MHA"), "/tmp/cut.MHA");
  EXPECT_EQ(PL::WithVoxmapExtension("/tmp/cut.txt"), "/tmp/cut.txt");
  EXPECT_EQ(PL::WithVoxmapExtension("/tmp/a.b/cut"), "/tmp/a.b/cut.nrrd");
  EXPECT_EQ(PL::WithVoxmapExtension(""), "");
}

TEST(PanelLogic, StateInWords) {
  using S = bm::SessionState;
  EXPECT_EQ(PL::StateText(S::Idle, ""), "");
  EXPECT_EQ(PL::StateText(S::Running, "none"), "running");
  EXPECT_EQ(PL::StateText(S::Paused, bm::ToString(bm::PauseReason::Overrun)), "paused: overrun");
  EXPECT_EQ(PL::StateText(S::Paused, ""), "paused");
  EXPECT_EQ(PL::StateText(S::Stopped, "user"), "stopped");
  EXPECT_TRUE(PL::IsPaused(S::Paused));
  EXPECT_FALSE(PL::IsPaused(S::Running));
  EXPECT_TRUE(PL::IsActive(S::Running) && PL::IsActive(S::Paused));
  EXPECT_FALSE(PL::IsActive(S::Idle) || PL::IsActive(S::Stopped));
}

TEST(PanelLogic, ForceScaleRange) {
  EXPECT_DOUBLE_EQ(PL::DefaultForceScale(), 0.0); // the tool's
  EXPECT_EQ(PL::ForceScaleError(PL::DefaultForceScale()), "");
  EXPECT_EQ(PL::ForceScaleError(1.0), "");
  EXPECT_NE(PL::ForceScaleError(1e-4), "");
  EXPECT_NE(PL::ForceScaleError(-1.0), "");
  EXPECT_NE(PL::ForceScaleError(PL::MaxForceScale() * 2), "");
  EXPECT_LT(PL::MinForceScale(), 1.0);
}

TEST(PanelLogic, ExpectedCostIsTheNearestMeasuredCell) {
  const std::string path = testing::TempDir() + "PanelLogicBench.csv";
  {
    std::ofstream csv(path);
    csv << "method,backend,shell,voxmap,status,median_ms,p99_ms,force_error\n"
           "lazar,cpu,128,128,ok,0.05,0.1,0.004\n"
           "lazar,cpu,256,256,ok,0.09,0.19,0.0003\n"
           "zheng,cpu,128,128,ok,0.27,0.45,0.0024\n";
  }
  const PL::ExpectedCost cost(bm::BenchmarkTable::Load(path));
  std::remove(path.c_str());
  EXPECT_EQ(cost.Line("drilling", 64, 113, vtkBMSessionSource::ZHENG),
            "Expected (zheng, shell 113 / voxmap 64, nearest measured: 128 / 128): frame 0.27 ms "
            "median, 0.45 ms p99; force error 0.24 %");
  EXPECT_EQ(cost.Line("drilling", 300, 300, vtkBMSessionSource::LAZAR).substr(0, 60),
            "Expected (lazar, shell 300 / voxmap 300, nearest measured: 2");
  // A p99 over the period warns before Start.
  EXPECT_EQ(cost.Line("drilling", 64, 113, vtkBMSessionSource::ZHENG, 0.25),
            "Expected (zheng, shell 113 / voxmap 64, nearest measured: 128 / 128): frame 0.27 ms "
            "median, 0.45 ms p99; force error 0.24 %; over the 0.25 ms period: expect overrun "
            "pauses, choose coarser resolutions");
  EXPECT_NE(cost.Line("no-such-scene.json", 0, 0, 0).find("Expected cost unknown"),
            std::string::npos);
}

// A scene with its own session measurements is expected from them (the hand-like trial of that
// scene), not from the drilling bench; another method, or a scene without rows, uses the bench.
TEST(PanelLogic, ExpectedCostOfASceneWithSessionMeasurements) {
  const std::string path = testing::TempDir() + "PanelLogicBench2.csv";
  {
    std::ofstream csv(path);
    csv << "method,backend,shell,voxmap,status,median_ms,p99_ms,force_error\n"
           "lazar,cpu,128,128,ok,0.05,0.1,0.004\n"
           "zheng,cpu,128,128,ok,0.27,0.45,0.0024\n";
  }
  const std::vector<bm::SessionBenchRow> sessions = bm::ParseSessionBenchCsv(
      bm::SessionBenchCsvHeader() +
          "\nglenoid,96,170,1,incremental,1,1,10000,0.31,0.9,2.5,40,0,10,\"CPU, 2 "
          "cores\",2026-11-26,cpu"
          "\nglenoid,96,170,1,incremental,1,2,10000,0.35,0.8,3.5,42,1,10,\"CPU, 2 "
          "cores\",2026-11-26,cpu"
          "\nglenoid,96,170,1,incremental,0,1,10000,0.2,0.5,1.5,0,0,10,\"CPU, 2 "
          "cores\",2026-11-26,cpu"
          "\nglenoid,96,170,1,full,1,1,10000,3.1,9.0,12.5,9000,80,10,\"CPU, 2 "
          "cores\",2026-11-26,cpu"
          "\nglenoid,192,340,1,incremental,0,1,10000,2.3,10.9,20,3000,40,10,\"CPU, 2 cores\","
          "2026-11-26,cpu\n",
      "sessions");
  const std::string path2 = path + ".copy";
  std::filesystem::copy_file(path, path2, std::filesystem::copy_options::overwrite_existing);
  const PL::ExpectedCost cost(bm::BenchmarkTable::Load(path), sessions);
  std::remove(path.c_str());
  // voxmap 100 alone: the shell scales alike (177); nearest cell 96 / 170 with the view (the
  // panel's session refreshes it), the worst p99 and max of its two runs, the median of their
  // p50s, their pauses and time summed.
  EXPECT_EQ(
      cost.Line("glenoid", 100, 0, 0),
      "Expected (glenoid session, shell 177 / voxmap 100, nearest measured: 170 / 96, "
      "hand-like trial with the live view on CPU, 2 cores, 2026-11-26): frame 0.35 ms median, "
      "0.9 ms p99, "
      "3.5 ms max; 1 overrun pauses in 20 s; force error 0.4 %; over the 1 ms period: "
      "expect overrun pauses, choose coarser resolutions");
  // 192 / 340 was measured only without the view: those figures, said so.
  EXPECT_EQ(cost.Line("glenoid", 192, 340, vtkBMSessionSource::LAZAR).substr(0, 112),
            "Expected (glenoid session, shell 340 / voxmap 192, nearest measured: 340 / 192, "
            "hand-like trial without the view");
  // No session cell within 1.5 x of voxmap 512: the bench.
  EXPECT_EQ(cost.Line("glenoid", 512, 512, 0).substr(0, 26), "Expected (lazar, shell 512");
  // Zheng's method was not measured in a session: the bench.
  EXPECT_EQ(cost.Line("glenoid", 100, 0, vtkBMSessionSource::ZHENG).substr(0, 26),
            "Expected (zheng, shell 177");
  // A scene without session rows: the bench.
  EXPECT_EQ(cost.Line("drilling", 64, 113, 0).substr(0, 26), "Expected (lazar, shell 113");
  // Neither resolution set: those the session chooses. With the view, 96 / 170 holds 1 kHz with
  // one thread at 0.9 ms p99 (its worse run), 192 was not measured with the view: 96 / 170.
  EXPECT_EQ(cost.Line("glenoid", 0, 0, 0).substr(0, 152),
            "Expected (glenoid session, shell 170 / voxmap 96, chosen for the session (1 engine "
            "thread; a CT bone's spacing may lower it), nearest measured: 170 / 96");
  // A 0.5 ms period: nothing holds, the coarsest measured is chosen and the line warns.
  const std::string fast = cost.Line("glenoid", 0, 0, 0, 0.5);
  EXPECT_NE(fast.find("voxmap 96, chosen for the session"), std::string::npos) << fast;
  EXPECT_NE(fast.find("expect overrun pauses"), std::string::npos) << fast;
  // With the session accuracy table, the line says what the voxmap buys (its row at 96).
  const std::vector<bm::SessionAccuracyRow> accuracy = bm::ParseSessionAccuracyCsv(
      bm::SessionAccuracyCsvHeader() +
          "\nglenoid,96,170,0.4296875,1,0.9,2140,0.86,0.4,0.94,-2.57,-0.031,0.37,-0.06,384,680,"
          "1.5,\"CPU, 2 cores\",2026-11-29\n",
      "accuracy");
  const PL::ExpectedCost withAccuracy(bm::BenchmarkTable::Load(path2), sessions, accuracy);
  std::remove(path2.c_str());
  const std::string bought = withAccuracy.Line("glenoid", 0, 0, 0);
  EXPECT_NE(bought.find("force error 0.4 %; its result against the converged reference (voxmap "
                        "384): removed volume -2.6 %, the face's depth -0.03 mm and orientation "
                        "0.37 deg, seating -0.1 points (0.430 mm voxels; CPU, 2 cores, "
                        "2026-11-29)"),
            std::string::npos)
      << bought;
  // No row at 192: nothing said about its accuracy.
  EXPECT_EQ(withAccuracy.Line("glenoid", 192, 340, 0).find("converged reference"),
            std::string::npos);
  // A damaged table names the line and column.
  try {
    bm::ParseSessionBenchCsv(bm::SessionBenchCsvHeader() +
                                 "\nglenoid,96,170,1,sideways,0,1,1,1,1,1,0,0,1,m,d,cpu\n",
                             "t.csv");
    ADD_FAILURE() << "a path other than incremental/full was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("t.csv:2: column 'path'"), std::string::npos) << e.what();
  }
}

TEST(PanelLogic, PointListsAreReadOrRefusedNamingThePoint) {
  std::vector<double> xyz;
  EXPECT_EQ(PL::ParsePoints("10 0 -5; 12.5, 3, -5", xyz), "");
  EXPECT_EQ(xyz, (std::vector<double>{10, 0, -5, 12.5, 3, -5}));
  EXPECT_EQ(PL::ParsePoints("  ", xyz), "");
  EXPECT_TRUE(xyz.empty());
  EXPECT_EQ(PL::ParsePoints("1 2 3;", xyz), "");
  EXPECT_EQ(xyz.size(), 3u);
  EXPECT_EQ(PL::ParsePoints("1 2 3; 4 5", xyz), "point 2 (' 4 5'): give three numbers x y z (mm)");
  EXPECT_TRUE(xyz.empty());
  EXPECT_EQ(PL::ParsePoints("1 2 3 4", xyz), "point 1 ('1 2 3 4'): give three numbers x y z (mm)");
  EXPECT_EQ(PL::ParsePoints("1 2 x", xyz), "point 1 ('1 2 x'): give three numbers x y z (mm)");
  EXPECT_EQ(PL::ParsePoints("1 2 3;; 4 5 6", xyz),
            "point 2 is empty: give three numbers x y z (mm)");
}
