// vtkBMGlenoidPlanFilter on the scapula phantom's voxmap (1 mm voxels, no CT): the measured
// version and inclination against the phantom's truth, a moved trigonum changing Friedman's
// version by the angle it was turned through without a new joint detection, the plan's targets,
// the plan scene, the glenoid placed by a click on its face or on its rim where detection fails,
// the report written as bmsim plan writes it, a bone without a glenoid refused with "no
// glenoid found", and a humeral head joined to the glenoid cut off as bmsim plan cuts it.
#include "vtkBMGlenoidPlanFilter.h"

#include "bmBoneFractionImage.h"
#include "bmPlanGlyphs.h"
#include "bmScapulaPhantom.h"
#include "bmScapulaVoxmap.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
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

  // The output: the plan's glyphs, every part (the axis, the normal, the reamer's outline, the
  // rim, the three landmarks) in its colour; the plan's camera down the axis.
  vtkPolyData* out = f->GetOutput();
  auto* part = vtkIntArray::SafeDownCast(out->GetCellData()->GetArray("Part"));
  ASSERT_NE(part, nullptr);
  ASSERT_NE(out->GetPointData()->GetArray("Colors"), nullptr);
  std::set<int> parts;
  for (vtkIdType i = 0; i < part->GetNumberOfValues(); ++i)
    parts.insert(part->GetValue(i));
  EXPECT_EQ(parts.size(), size_t(bm::kPlanGlyphParts));
  const double* cam = f->GetPlanCamera();
  const double* axis = f->GetPlanAxis();
  EXPECT_NEAR(cam[3] * axis[0] + cam[4] * axis[1] + cam[5] * axis[2], std::cos(30 * kPi / 180),
              1e-9);
  EXPECT_NEAR(cam[0], f->GetPlanEntry()[0], 1e-12);

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

TEST(GlenoidPlanFilter, AClickOnTheFaceOrTheRimPlacesTheGlenoidAndTheReportIsWritten) {
  // The scapula without its humeral head: detection finds no joint; a point clicked on the face
  // (3 mm off the centre) and then four points clicked on the rim each give the glenoid.
  PhantomInput& in = Phantom();
  const bm::ScapulaTruth& t = in.phantom.Truth();
  bm::Voxmap v = bm::MakeScapulaVoxmap(in.phantom, 1.0, 3);
  for (int k = 0; k < v.Dims()[2]; ++k)
    for (int j = 0; j < v.Dims()[1]; ++j)
      for (int i = 0; i < v.Dims()[0]; ++i) {
        const bm::Vec3 p{v.Origin()[0] + i * v.Spacing(), v.Origin()[1] + j * v.Spacing(),
                         v.Origin()[2] + k * v.Spacing()};
        if (bm::Distance(p, t.humeralHeadCentre) <= t.humeralHeadRadiusMm + 2)
          v.SetFill(v.Index(i, j, k), 0);
      }
  bm::BoneFractionImage image;
  image.Update(v);
  vtkNew<vtkBMGlenoidPlanFilter> f;
  f->SetInputData(image.GetOutput());
  f->SetCTFileName("/tmp/scapula-ct");
  f->Update();
  EXPECT_NE(std::string(f->GetLastError()).find("Click the face"), std::string::npos)
      << f->GetLastError();
  // The failure's report says why.
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "bm-plan-filter-report";
  fs::remove_all(dir);
  f->SetReportDirectory(dir.string().c_str());
  ASSERT_TRUE(f->WriteReport()) << f->GetReportError();
  EXPECT_FALSE(fs::exists(dir / "plan.json"));
  {
    std::ifstream report(dir / "plan_report.json");
    const nlohmann::json j = nlohmann::json::parse(report);
    EXPECT_EQ(j.at("status"), "no_glenoid");
  }

  const bm::Vec3 click = bm::AddScaled(t.glenoidCentre, t.anteriorAxis, 3.0);
  f->SetFacePoint(click[0], click[1], click[2]);
  f->UseFacePointOn();
  f->Update();
  ASSERT_STREQ(f->GetLastError(), "");
  const double* c = f->GetUsedGlenoidCentre();
  EXPECT_LT(bm::Distance({c[0], c[1], c[2]}, t.glenoidCentre), 1.0);
  const double* n = f->GetUsedFaceNormal();
  EXPECT_LT(bm::AngleDeg({n[0], n[1], n[2]}, t.faceNormal), 1.0);
  EXPECT_NEAR(f->GetVersion3D(), t.version3DDeg, 1.0);

  // The report as bmsim plan writes it: the plan, its steps, the report saying planned.
  fs::remove_all(dir);
  ASSERT_TRUE(f->WriteReport()) << f->GetReportError();
  for (const char* name : {"plan.json", "step1-guide-pin.json", "step2-ream.json", "plan_report.md",
                           "plan_report.html", "plan_report.json"})
    EXPECT_TRUE(fs::exists(dir / name)) << name;
  EXPECT_NE(std::string(f->GetReportFiles()).find("plan_report.html"), std::string::npos);
  {
    std::ifstream report(dir / "plan_report.json");
    const nlohmann::json j = nlohmann::json::parse(report);
    EXPECT_EQ(j.at("status"), "planned");
    std::ifstream plan(dir / "plan.json");
    EXPECT_EQ(nlohmann::json::parse(plan).at("bone").at("ct").at("ct"), "/tmp/scapula-ct");
  }
  fs::remove_all(dir);
  f->SetReportDirectory(nullptr);
  EXPECT_FALSE(f->WriteReport());
  EXPECT_NE(std::string(f->GetReportError()).find("folder"), std::string::npos);

  // Four points on the rim, the face point off.
  f->UseFacePointOff();
  const bm::Vec3 up = bm::Normalized(
      bm::AddScaled(t.superiorAxis, t.faceNormal, -bm::Dot(t.superiorAxis, t.faceNormal)));
  const bm::Vec3 across = bm::Cross(t.faceNormal, up);
  for (const auto& [a, b] : {std::pair{19.0, 0.0}, {0.0, 14.0}, {-19.0, 0.0}, {0.0, -14.0}}) {
    const bm::Vec3 p = bm::AddScaled(bm::AddScaled(t.glenoidCentre, up, a), across, b);
    f->AddRimPoint(p[0], p[1], p[2]);
  }
  EXPECT_EQ(f->GetNumberOfRimPoints(), 4);
  f->Update();
  ASSERT_STREQ(f->GetLastError(), "");
  c = f->GetUsedGlenoidCentre();
  EXPECT_LT(bm::Distance({c[0], c[1], c[2]}, t.glenoidCentre), 1.0);
  f->RemoveAllRimPoints();
  f->Update();
  EXPECT_NE(std::string(f->GetLastError()).find("no glenoid found"), std::string::npos);
}

TEST(GlenoidPlanFilter, AJoinedHumeralHeadIsCutOffAndTheStepsLeaveItOut) {
  // The joint space bridged over a disc 24 mm across, as thick slices fuse it: one bone, no
  // joint; the plan cuts the head off along its sphere, measures the glenoid and its steps'
  // bone leaves the head out, as bmsim plan does.
  PhantomInput& in = Phantom();
  const bm::ScapulaTruth& t = in.phantom.Truth();
  bm::Voxmap v = bm::MakeScapulaVoxmap(in.phantom, 1.0, 3);
  bm::BridgeJointSpace(v, in.phantom, 12.0);
  bm::BoneFractionImage image;
  image.Update(v);
  vtkNew<vtkBMGlenoidPlanFilter> f;
  f->SetInputData(image.GetOutput());
  f->SetCTFileName("/tmp/scapula-ct");
  f->Update();
  ASSERT_STREQ(f->GetLastError(), "");
  const double* c = f->GetUsedGlenoidCentre();
  EXPECT_LT(bm::Distance({c[0], c[1], c[2]}, t.glenoidCentre), 2.0);
  EXPECT_NEAR(f->GetVersion3D(), t.version3DDeg, 2.0);
  EXPECT_NEAR(f->GetInclination(), t.inclinationDeg, 2.0);
  for (const char* scene : {f->GetPinStepScene(), f->GetReamStepScene()}) {
    const nlohmann::json j = nlohmann::json::parse(scene);
    ASSERT_TRUE(j["bone"]["ct"].contains("exclude_heads")) << j["bone"].dump();
    const auto& head = j["bone"]["ct"]["exclude_heads"][0];
    const bm::Vec3 hc{head["centre_mm"][0], head["centre_mm"][1], head["centre_mm"][2]};
    EXPECT_LT(bm::Distance(hc, t.humeralHeadCentre), 1.5);
  }
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "bm-plan-filter-joined";
  fs::remove_all(dir);
  f->SetReportDirectory(dir.string().c_str());
  ASSERT_TRUE(f->WriteReport()) << f->GetReportError();
  std::ifstream report(dir / "plan_report.md");
  const std::string text((std::istreambuf_iterator<char>(report)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("cut off along its sphere"), std::string::npos);
}
