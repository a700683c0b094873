// The reaming accuracy (bmReamingAccuracy.h): the glenoid scene's reamer fed 2 mm into the
// analytic glenoid (bmTestGlenoid.h) at two resolutions, each outcome measured and compared with
// the finer one; the comparison's arithmetic on outcomes set by hand; refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "../Session/bmTestGlenoid.h"
#include "bmReamingAccuracy.h"

namespace {

// The analytic glenoid's scene at voxmap `v` (the shell at the built-in scene's ratio 340 / 192),
// the reamer from 1.5 mm above the face centre to 2 mm below it at 0.4 mm/rev (four times the
// scene's feed, a quarter of the frames; the geometry cut is the same).
bm::Scene Scene(int v) {
  nlohmann::json j = bmtest::AnalyticGlenoidScene(v, int(std::lround(v * 340.0 / 192))).ToJson();
  j["trial"]["entry_mm"] = {0, 0, 0};
  j["trial"]["axis"] = {0, 0, 1};
  j["trial"]["clearance_mm"] = 1.5;
  j["trial"]["depth_mm"] = 2.0;
  j["trial"]["feed_mm_per_rev"] = 0.4;
  return bm::Scene::FromJson(j);
}

bm::ReamingTrialOutcome Trial(int v) {
  return bm::RunReamingTrial(Scene(v),
                             bmtest::AnalyticGlenoidVoxmap(bmtest::AnalyticGlenoidSpacing(v)),
                             bm::GlenoidPhantomOutcomeOptions());
}

TEST(ReamingAccuracy, CoarseTrialConvergesOnTheFineOne) {
  const bm::ReamingTrialOutcome coarse = Trial(48), fine = Trial(96);
  EXPECT_EQ(coarse.voxmap, 48);
  EXPECT_EQ(fine.shell, 170);
  EXPECT_NEAR(fine.voxelMm, 41.25 / 96, 1e-9);
  // Both reached the scene's depth and cut a face square to the axis; the convex reamer's face
  // (2 mm deep at its deepest ring, shallower towards its rim) fits a plane about 0.9 mm deep.
  for (const auto* t : {&coarse, &fine}) {
    EXPECT_NEAR(t->outcome.reachedDepthMm, 2.0, 0.01);
    EXPECT_GT(t->outcome.removedMm3, 100.0);
    EXPECT_LT(t->outcome.faceAngleDeg, 2.0);
    EXPECT_GT(t->outcome.seating, 0.5);
    EXPECT_GT(t->outcome.faceDepthMm, 0.5);
    EXPECT_LT(t->outcome.faceDepthMm, 2.0);
  }
  const bm::ReamingAccuracy a = bm::CompareReamingOutcomes(coarse.outcome, fine.outcome);
  // 0.86 mm voxels against 0.43 mm: the removed volume within a tenth, the face's depth within a
  // fifth of a coarse voxel, its orientation within 2 deg (measured: -3.3 %, -0.04 mm, 0.2 deg).
  EXPECT_LT(std::abs(a.removedErrorPct), 10.0);
  EXPECT_LT(std::abs(a.depthErrorMm), 0.2 * 41.25 / 48);
  EXPECT_LT(a.faceErrorDeg, 2.0);
  EXPECT_NEAR(a.reachedErrorMm, 0.0, 0.01);
  // A trial compared with itself is exact.
  const bm::ReamingAccuracy self = bm::CompareReamingOutcomes(fine.outcome, fine.outcome);
  EXPECT_EQ(self.removedErrorPct, 0.0);
  EXPECT_EQ(self.depthErrorMm, 0.0);
  EXPECT_EQ(self.faceErrorDeg, 0.0);
  EXPECT_EQ(self.seatingErrorPct, 0.0);
}

TEST(ReamingAccuracy, ComparisonArithmetic) {
  bm::ReamingOutcome ref, cell;
  ref.removedMm3 = 400;
  ref.faceDepthMm = 2.0;
  ref.faceNormal = {0, 0, 1};
  ref.seating = 0.90;
  ref.reachedDepthMm = 2.0;
  cell.removedMm3 = 380;
  cell.faceDepthMm = 1.75;
  cell.faceNormal = {0, std::sin(0.05), std::cos(0.05)};
  cell.seating = 0.84;
  cell.reachedDepthMm = 1.9;
  const bm::ReamingAccuracy a = bm::CompareReamingOutcomes(cell, ref);
  EXPECT_NEAR(a.removedErrorPct, -5.0, 1e-12);
  EXPECT_NEAR(a.depthErrorMm, -0.25, 1e-12);
  EXPECT_NEAR(a.faceErrorDeg, 0.05 * 180 / M_PI, 1e-9);
  EXPECT_NEAR(a.seatingErrorPct, -6.0, 1e-9);
  EXPECT_NEAR(a.reachedErrorMm, -0.1, 1e-12);
  ref.removedMm3 = 0;
  EXPECT_THROW(bm::CompareReamingOutcomes(cell, ref), std::invalid_argument);
}

TEST(ReamingAccuracy, RefusesATrialWithoutAReamer) {
  nlohmann::json j = Scene(48).ToJson();
  j["tool"] = {{"type", "drill"}};
  try {
    bm::RunReamingTrial(bm::Scene::FromJson(j), bmtest::AnalyticGlenoidVoxmap(41.25 / 48),
                        bm::GlenoidPhantomOutcomeOptions());
    FAIL() << "a drill's trial was measured as a reaming";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not a reamer"), std::string::npos) << e.what();
  }
}

} // namespace
