// vtkBMGlenoidPlanFilter on the scapula phantom's voxmap (1 mm voxels, no CT): the measured
// version and inclination against the phantom's truth, a moved trigonum changing Friedman's
// version by the angle it was turned through without a new joint detection, the plan's targets,
// the plan scene, and a bone without a glenoid refused with "no glenoid found".
#include "vtkBMGlenoidPlanFilter.h"

#include "bmBoneFractionImage.h"
#include "bmScapulaPhantom.h"
#include "bmScapulaVoxmap.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The default phantom (12 deg retroversion, 8 deg superior inclination) as the filter's input.
struct PhantomInput {
  bm::ScapulaPhantom phantom{bm::ScapulaPhantomParams{}};
  bm::BoneFractionImage image;
  PhantomInput() { image.Update(bm::MakeScapulaVoxmap(phantom, 1.0, 3)); }
};

PhantomInput& Phantom() {
  static PhantomInput p; // sampled once for all tests (a few seconds)
  return p;
}

/// p turned by `deg` about the vertical (z) axis through c.
bm::Vec3 TurnAboutVertical(const bm::Vec3& p, const bm::Vec3& c, double deg) {
  const double a = deg * kPi / 180, x = p[0] - c[0], y = p[1] - c[1];
  return {c[0] + std::cos(a) * x - std::sin(a) * y, c[1] + std::sin(a) * x + std::cos(a) * y, p[2]};
}

} // namespace

TEST(GlenoidPlanFilter, MeasuresThePhantomAndFollowsAMovedTrigonum) {
  PhantomInput& in = Phantom();
  const bm::ScapulaTruth& t = in.phantom.Truth();
  vtkNew<vtkBMGlenoidPlanFilter> f;
  f->SetInputData(in.image.GetOutput());
  f->Update();
  ASSERT_STREQ(f->GetLastError(), "");
  EXPECT_NEAR(f->GetFriedmanVersion(), t.friedmanVersionDeg, 1.0);
  EXPECT_NEAR(f->GetVersion3D(), t.version3DDeg, 1.0);
  EXPECT_NEAR(f->GetInclination(), t.inclinationDeg, 1.0);
  EXPECT_NEAR(f->GetGlenoidHeight(), t.glenoidHeightMm, 1.5);
  EXPECT_NEAR(f->GetGlenoidWidth(), t.glenoidWidthMm, 1.5);
  const double* c = f->GetUsedGlenoidCentre();
  EXPECT_LT(
      std::hypot(c[0] - t.glenoidCentre[0], c[1] - t.glenoidCentre[1], c[2] - t.glenoidCentre[2]),
      1.0);
  EXPECT_EQ(f->GetDetectionCount(), 1);
  // Default targets 0 / 0: the correction is the angle from the measured face to neutral.
  EXPECT_GT(f->GetCorrection(), 5.0);
  EXPECT_STREQ(f->GetPlanScene(), ""); // no CT named

  // The output: 3 landmark vertices, the rim, the axis and the normal.
  vtkPolyData* out = f->GetOutput();
  EXPECT_EQ(out->GetNumberOfVerts(), 3);
  EXPECT_EQ(out->GetNumberOfLines(), 4);
  ASSERT_NE(out->GetCellData()->GetArray("Part"), nullptr);

  // Drag the trigonum 5 deg about the vertical through the glenoid line's midpoint: Friedman's
  // scapular axis (trigonum to that midpoint) turns 5 deg, so his version changes by 5 deg; no
  // new detection.
  const double before = f->GetFriedmanVersion(), before3D = f->GetVersion3D();
  const double* used = f->GetUsedTrigonum();
  const double* line = f->GetGlenoidLine();
  const bm::Vec3 mid{(line[0] + line[3]) / 2, (line[1] + line[4]) / 2, (line[2] + line[5]) / 2};
  const bm::Vec3 moved = TurnAboutVertical({used[0], used[1], used[2]}, mid, 5.0);
  f->SetTrigonum(moved[0], moved[1], moved[2]);
  f->UseTrigonumOn();
  f->Update();
  ASSERT_STREQ(f->GetLastError(), "");
  EXPECT_NEAR(std::abs(f->GetFriedmanVersion() - before), 5.0, 0.05);
  EXPECT_GT(std::abs(f->GetVersion3D() - before3D), 1.0);
  EXPECT_EQ(f->GetDetectionCount(), 1);
  EXPECT_NEAR(f->GetUsedTrigonum()[0], moved[0], 1e-9);

  // Back to the detected trigonum: the first angles again, still one detection.
  f->UseTrigonumOff();
  f->Update();
  EXPECT_NEAR(f->GetFriedmanVersion(), before, 1e-9);
  EXPECT_EQ(f->GetDetectionCount(), 1);
}

TEST(GlenoidPlanFilter, TargetsSetTheAxisAndTheSceneHasBothSteps) {
  PhantomInput& in = Phantom();
  vtkNew<vtkBMGlenoidPlanFilter> f;
  f->SetInputData(in.image.GetOutput());
  f->SetTargetVersion(-12.0);
  f->SetTargetInclination(8.0);
  f->SetCTFileName("/tmp/scapula-ct");
  f->Update();
  ASSERT_STREQ(f->GetLastError(), "");
  // Targets at the phantom's own angles: the axis is the face normal, within the measurement.
  EXPECT_LT(f->GetCorrection(), 1.5);
  const nlohmann::json scene = nlohmann::json::parse(f->GetPlanScene());
  ASSERT_EQ(scene.at("steps").size(), 2u);
  EXPECT_EQ(scene["steps"][0]["name"], "guide pin");
  EXPECT_EQ(scene["steps"][1]["name"], "ream");
  EXPECT_EQ(scene["bone"]["ct"]["ct"], "/tmp/scapula-ct");
  EXPECT_TRUE(scene["planning"].contains("landmarks"));
  const nlohmann::json pin = nlohmann::json::parse(f->GetPinStepScene());
  const nlohmann::json ream = nlohmann::json::parse(f->GetReamStepScene());
  EXPECT_EQ(pin.at("tool").at("type"), "drill");
  EXPECT_EQ(ream.at("tool").at("type"), "reamer");

  // A bad setting is refused by name.
  f->SetReamDepth(-1.0);
  f->Update();
  EXPECT_NE(std::string(f->GetLastError()).find("ream"), std::string::npos) << f->GetLastError();
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(GlenoidPlanFilter, ABoneWithoutAGlenoidAsksForLandmarks) {
  bm::Voxmap block({40, 40, 40}, 1.0, {0, 0, 0});
  for (int k = 10; k < 30; ++k)
    for (int j = 10; j < 30; ++j)
      for (int i = 10; i < 30; ++i)
        block.SetFill(block.Index(i, j, k), bm::Voxmap::kFull);
  bm::BoneFractionImage image;
  image.Update(block);
  vtkNew<vtkBMGlenoidPlanFilter> f;
  f->SetInputData(image.GetOutput());
  f->Update();
  const std::string error = f->GetLastError();
  EXPECT_NE(error.find("no glenoid found"), std::string::npos) << error;
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(f->GetFriedmanVersion(), 0.0);
}
