// The drilling trial through the shared harness (bmMachiningSetup.h, bmFeedTrial.h): steady thrust
// and torque converge to the quadrature reference as shell and voxmap are refined; removal
// conserves material; the Zheng baseline runs through the same harness.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "bmEdgeQuadrature.h"
#include "bmFeedTrial.h"
#include "bmMachiningSetup.h"

namespace {

struct Level {
  int shell, voxmap;
};

// The drilling scene on its 5 x 5 x 1.5 mm block with the grids aligned 2:1 as in the default
// (shell spacing = half the voxel), fed 4x faster per frame than 1 kHz at 1000 rpm so the trial
// stays short (3.3 um/frame: still 6-24 frames per voxel at these grids). Forces depend on f and n
// only, not on the frame period.
bm::Scene DrillingScene(Level level, bm::Method method = bm::Method::Lazar) {
  bm::Scene s;
  s.shellResolution = level.shell;
  s.voxmapResolution = level.voxmap;
  s.method = method;
  s.threads = 2;
  s.trial.frameS = 0.004;
  return s;
}

struct TrialResult {
  nlohmann::json summary;
  double boneBefore = 0, boneAfter = 0, seconds = 0;
};

TrialResult RunTrial(const bm::Scene& s) {
  const auto t0 = std::chrono::steady_clock::now();
  bm::MachiningSetup setup(s, bm::MakeSceneBlock(s));
  TrialResult r;
  r.boneBefore = setup.Bone().BoneVolume();
  bm::FeedTrial trial(setup);
  EXPECT_TRUE(trial.Run());
  r.boneAfter = setup.Bone().BoneVolume();
  r.summary = trial.Summary();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

double Get(const TrialResult& r, const char* key) {
  return r.summary.at(key).get<double>();
}

// Measured (Release), default drilling set: thrust error +0.04 % / -0.03 % / -0.00 %, torque
// -0.00 % at 256/64, 512/128, 1024/256. With the assumed set (k_f = 0.5 on the chisel) the thrust
// error was +0.47 % / +0.55 % / +0.37 % and did not fall monotonically: the point shell's
// midpoint rule over the force bins in the chisel's first bin, where the feed angle turns within
// a few um of the axis (TestPointShell). Asserted: within 1 % at the finest level and no worse
// there than at the coarsest (0.2 % slack).
TEST(FeedTrial, SteadyForcesConvergeToTheQuadratureReference) {
  const std::vector<Level> levels{{256, 64}, {512, 128}, {1024, 256}};
  std::vector<double> thrustErr, torqueErr;
  std::printf("shell voxmap  thrust N (ref)       torque N mm (ref)     err T     err M     ripple "
              "  lateral N  s\n");
  for (const Level& l : levels) {
    const TrialResult r = RunTrial(DrillingScene(l));
    const double eT = Get(r, "thrust_error"), eM = Get(r, "torque_error");
    std::printf("%5d %6d  %7.4f (%7.4f)  %7.4f (%7.4f)  %+8.4f  %+8.4f  %7.5f  %8.5f  %.1f\n",
                l.shell, l.voxmap, Get(r, "thrust_N"), Get(r, "reference_thrust_N"),
                Get(r, "torque_Nmm"), Get(r, "reference_torque_Nmm"), eT, eM,
                Get(r, "thrust_ripple"), Get(r, "lateral_N"), r.seconds);
    EXPECT_GT(r.summary.at("engaged_frames").get<int>(), 20);
    EXPECT_EQ(r.summary.at("statistics_phase"), "full_engagement");
    thrustErr.push_back(std::abs(eT));
    torqueErr.push_back(std::abs(eM));
    // Symmetric shell at full engagement: the lateral force is a small fraction of the thrust.
    EXPECT_LT(Get(r, "lateral_N"), 0.01 * Get(r, "thrust_N"));
  }
  // Within 1 % at the finest level, and closer there than at the coarsest.
  EXPECT_LT(thrustErr.back(), 0.01);
  EXPECT_LT(torqueErr.back(), 0.01);
  EXPECT_LE(thrustErr.back(), std::max(thrustErr.front(), 0.002));
  EXPECT_LE(torqueErr.back(), std::max(torqueErr.front(), 0.002));
}

// Removal conserves material. Exactly: what the frames report as removed is what left the voxmap.
// Within tolerance: it is what the tool envelope swept. The frames remove a little less than the
// engaged elements ask for (an element may only empty its own voxel; requests past empty clip),
// and less than the analytic volume below the final depth: where the two grids alias, voxels at
// the hole's wall hold more or less element area than their cross-section, so some of the wall
// is left standing (the lead measured ~5 % short at the default 2:1 grids; here, at 512/128,
// -0.5 % vs swept and -3.1 % vs analytic). Asserted: within 8 % of both.
TEST(FeedTrial, RemovedVolumeEqualsSweptVolume) {
  const TrialResult r = RunTrial(DrillingScene({512, 128}));
  const double removed = Get(r, "removed_volume_mm3"), swept = Get(r, "swept_volume_mm3"),
               analytic = Get(r, "analytic_removed_volume_mm3");
  std::printf(
      "removed %.5f mm^3, swept (requested) %.5f mm^3 (%+.2f %%), analytic %.5f mm^3 (%+.2f %%), "
      "bone lost %.5f mm^3\n",
      removed, swept, 100 * (removed - swept) / swept, analytic,
      100 * (removed - analytic) / analytic, r.boneBefore - r.boneAfter);
  EXPECT_NEAR(r.boneBefore - r.boneAfter, removed, 1e-9 * r.boneBefore);
  EXPECT_LE(removed, swept * (1 + 1e-12));
  EXPECT_NEAR(removed, swept, 0.08 * swept);
  EXPECT_NEAR(removed, analytic, 0.08 * analytic);
  EXPECT_NEAR(Get(r, "removed_volume_error"), (removed - analytic) / analytic, 1e-12);
  const bm::Scene s = DrillingScene({512, 128});
  EXPECT_NEAR(
      analytic,
      bm::VolumeBelowDepth(bm::TwistDrill(), bm::FullEngagementDepth(bm::TwistDrill()) + 0.3),
      1e-9);
  (void)s;
}

// A finer voxmap needs a finer shell: Scene::WithVoxmapResolution keeps the grids' ratio. The
// drilling scene at 128/32 (2:1) taken to voxmap 128 gets shell 512 and removes what the drill
// sweeps; keeping shell 128 at voxmap 128 (element spacing two voxels, as the glenoid's shell 340
// at voxmap 512 is 1.3) leaves voxels that no element visits standing.
TEST(FeedTrial, AFinerVoxmapKeepsTheShellRatioAndTheRemovedVolume) {
  const bm::Scene base = DrillingScene({128, 32});
  const bm::Scene scaled = base.WithVoxmapResolution(128);
  EXPECT_EQ(scaled.voxmapResolution, 128);
  EXPECT_EQ(scaled.shellResolution, 512);
  EXPECT_EQ(base.WithVoxmapResolution(4096).shellResolution, 4096); // clamped
  EXPECT_THROW(base.WithVoxmapResolution(4), std::invalid_argument);
  bm::Scene coarse = scaled;
  coarse.shellResolution = base.shellResolution;
  const TrialResult a = RunTrial(scaled), b = RunTrial(coarse);
  const double analytic = Get(a, "analytic_removed_volume_mm3");
  const double ea = Get(a, "removed_volume_mm3") / analytic - 1,
               eb = Get(b, "removed_volume_mm3") / analytic - 1;
  std::printf("removed vs analytic: shell 512 at voxmap 128 %+.2f %%, shell 128 %+.2f %%\n",
              100 * ea, 100 * eb);
  EXPECT_NEAR(ea, 0.0, 0.08);
  EXPECT_LT(eb, ea - 0.05);
}

// Zheng et al.'s baseline through the same harness: finite, positive, near its own reference.
TEST(FeedTrial, ZhengRunsThroughTheSameHarness) {
  const TrialResult r = RunTrial(DrillingScene({256, 64}, bm::Method::Zheng));
  std::printf("zheng: thrust %.4f N (ref %.4f), torque %.4f N mm (ref %.4f), engine %s, removed "
              "%.5f mm^3, %.1f s\n",
              Get(r, "thrust_N"), Get(r, "reference_thrust_N"), Get(r, "torque_Nmm"),
              Get(r, "reference_torque_Nmm"), r.summary.at("engine").get<std::string>().c_str(),
              Get(r, "removed_volume_mm3"), r.seconds);
  EXPECT_EQ(r.summary.at("method"), "zheng");
  EXPECT_EQ(r.summary.at("engine"), "cpu/zheng-octree");
  for (const char* k : {"thrust_N", "torque_Nmm", "reference_thrust_N", "reference_torque_Nmm"}) {
    EXPECT_TRUE(std::isfinite(Get(r, k))) << k;
    EXPECT_GT(Get(r, k), 0.0) << k;
  }
  EXPECT_LT(std::abs(Get(r, "thrust_error")), 0.02);
  EXPECT_LT(std::abs(Get(r, "torque_error")), 0.02);
  EXPECT_NEAR(r.boneBefore - r.boneAfter, Get(r, "removed_volume_mm3"), 1e-9 * r.boneBefore);
}

// A trial stopped before full engagement compares like with like: its partly engaged mean against
// the reference integrated at its own frames' depths (flat block top), not against the fully
// engaged reference; the summary names the comparison and the coefficient set.
TEST(FeedTrial, PartialEngagementErrorsUseTheSameEngagement) {
  bm::Scene s = DrillingScene({512, 128});
  s.trial.depthMm = 0.3; // the tip's edges are fully engaged at 0.683 mm
  const TrialResult r = RunTrial(s);
  std::printf("partial: thrust %.4f N vs same-depth reference %.4f N (error %+.4f), fully engaged "
              "reference %.4f N (fraction %.3f); torque error %+.4f\n",
              Get(r, "thrust_N"), Get(r, "error_reference_thrust_N"), Get(r, "thrust_error"),
              Get(r, "reference_thrust_N"), Get(r, "thrust_fraction_of_full_engagement"),
              Get(r, "torque_error"));
  EXPECT_EQ(r.summary.at("statistics_phase"), "last_fifth_of_travel");
  EXPECT_EQ(r.summary.at("error_reference"), "partial_engagement_same_depths");
  // Against the fully engaged reference the torque would be 'wrong' by 80 %; against the
  // reference of its own engagement it is within the coarse grid's few %.
  const double torqueVsFull = Get(r, "torque_Nmm") / Get(r, "reference_torque_Nmm") - 1;
  std::printf("torque against the fully engaged reference: %+.4f\n", torqueVsFull);
  EXPECT_LT(torqueVsFull, -0.5);
  EXPECT_LT(Get(r, "thrust_fraction_of_full_engagement"), 0.95);
  EXPECT_LT(std::abs(Get(r, "thrust_error")), 0.02);
  EXPECT_LT(std::abs(Get(r, "torque_error")), 0.06);
  EXPECT_EQ(r.summary.at("coefficients").at("name"), "drilling-bovine-orelaja2020");
  EXPECT_EQ(r.summary.at("coefficients").at("calibrated"), true);
  // The full-engagement run says which comparison it made.
  const TrialResult f = RunTrial(DrillingScene({256, 64}));
  EXPECT_EQ(f.summary.at("error_reference"), "full_engagement");
  EXPECT_DOUBLE_EQ(Get(f, "error_reference_thrust_N"), Get(f, "reference_thrust_N"));
}

TEST(FeedTrial, PercentileByNearestRank) {
  std::vector<double> v{10, 1, 9, 2, 8, 3, 7, 4, 6, 5};
  EXPECT_EQ(bm::Percentile(v, 50), 5);
  EXPECT_EQ(bm::Percentile(v, 99), 10);
  EXPECT_EQ(bm::Percentile(v, 100), 10);
  EXPECT_EQ(bm::Percentile(v, 0), 1);
  EXPECT_EQ(bm::Percentile(v, 10), 1);
  EXPECT_EQ(bm::Percentile(v, 11), 2);
  EXPECT_EQ(bm::Percentile({}, 50), 0);
  EXPECT_EQ(bm::Percentile({3.5}, 99), 3.5);
}

} // namespace
