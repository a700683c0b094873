// The plan's glyphs (bmPlanGlyphs.h), as the 3D view and the report's pictures draw them: every
// part present in its own colour, labelled with its name in letters facing the plan's camera,
// tubes and spheres around the plan's geometry, and a plan without an axis refused by name.
#include "bmPlanGlyphs.h"

#include <vtkCellData.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>

namespace {

const nlohmann::json kPlanning = {
    {"entry_mm", {-118, 30.5, 60}},
    {"axis", {-1, 0, 0}},
    {"reamer_diameter_mm", 30},
    {"landmarks",
     {{"glenoid_centre_mm", {-120, 30, 60}},
      {"face_normal", {-0.94, -0.31, 0.14}},
      {"trigonum_mm", {-20, 60, 62}},
      {"inferior_angle_mm", {-40, 70, -50}},
      {"rim_mm", {{-120, 30, 75}, {-120, 42, 60}, {-120, 30, 45}, {-120, 18, 60}}}}}};

double Dot(const double a[3], const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

} // namespace

TEST(PlanGlyphs, EveryPartInItsColourAndLabelled) {
  const auto glyphs = bm::MakePlanGlyphs(kPlanning);
  auto* parts = vtkIntArray::SafeDownCast(glyphs->GetCellData()->GetArray("Part"));
  auto* colours = vtkUnsignedCharArray::SafeDownCast(glyphs->GetPointData()->GetArray("Colors"));
  ASSERT_NE(parts, nullptr);
  ASSERT_NE(colours, nullptr);
  ASSERT_EQ(colours->GetNumberOfComponents(), 3);
  std::set<int> seen;
  for (vtkIdType c = 0; c < glyphs->GetNumberOfCells(); ++c) {
    const int part = parts->GetValue(c);
    seen.insert(part);
    // Each cell's points carry its part's colour.
    const unsigned char* want = bm::PlanGlyphColour(bm::PlanGlyphPart(part));
    vtkIdType n;
    const vtkIdType* ids;
    glyphs->GetCellPoints(c, n, ids);
    for (vtkIdType i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(colours->GetValue(3 * ids[i] + k), want[k]) << "part " << part;
  }
  EXPECT_EQ(seen.size(), size_t(bm::kPlanGlyphParts));
  // The colours differ from each other.
  std::set<std::array<int, 3>> distinct;
  for (int p = 0; p < bm::kPlanGlyphParts; ++p) {
    const unsigned char* c = bm::PlanGlyphColour(bm::PlanGlyphPart(p));
    distinct.insert({c[0], c[1], c[2]});
  }
  EXPECT_EQ(distinct.size(), size_t(bm::kPlanGlyphParts));

  // Without labels: fewer cells, the same parts; the labels are the difference and lie in planes
  // facing the plan's camera.
  bm::PlanGlyphOptions bare;
  bare.labels = false;
  const auto unlabelled = bm::MakePlanGlyphs(kPlanning, bare);
  EXPECT_LT(unlabelled->GetNumberOfCells() + 100, glyphs->GetNumberOfCells());
  const bm::SurfaceView view = bm::PlanView(kPlanning);
  // The trigonum's label: the points added after its sphere, all at one depth along the view.
  double depthMin = 1e9, depthMax = -1e9;
  int labelPoints = 0;
  for (vtkIdType c = 0; c < glyphs->GetNumberOfCells(); ++c) {
    if (parts->GetValue(c) != int(bm::PlanGlyphPart::Trigonum))
      continue;
    vtkIdType n;
    const vtkIdType* ids;
    glyphs->GetCellPoints(c, n, ids);
    for (vtkIdType i = 0; i < n; ++i) {
      double x[3];
      glyphs->GetPoint(ids[i], x);
      const double d[3] = {x[0] + 20, x[1] - 60, x[2] - 62};
      if (std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) <= 1.5 + 1e-3)
        continue; // the sphere
      const double depth = Dot(x, view.toCamera);
      depthMin = std::min(depthMin, depth), depthMax = std::max(depthMax, depth);
      ++labelPoints;
    }
  }
  EXPECT_GT(labelPoints, 20);
  EXPECT_LT(depthMax - depthMin, 1e-4) << "the label does not face the plan's camera";
}

TEST(PlanGlyphs, TheCameraLooksDownTheAxisTilted) {
  const bm::SurfaceView view = bm::PlanView(kPlanning, 400);
  const std::array<double, 3> axis{-1, 0, 0};
  const double cosine =
      view.toCamera[0] * axis[0] + view.toCamera[1] * axis[1] + view.toCamera[2] * axis[2];
  EXPECT_NEAR(std::acos(cosine) * 180 / 3.14159265358979323846, 30.0, 1e-9);
  EXPECT_NEAR(Dot(view.viewUp.data(), view.toCamera), 0.0, 1e-12);
  EXPECT_NEAR(view.halfHeightMm, 1.4 * 15, 1e-12);
  EXPECT_EQ(view.focalMm[0], -118);
}

TEST(PlanGlyphs, APlanWithoutAnAxisIsRefusedByName) {
  try {
    bm::MakePlanGlyphs({{"entry_mm", {0, 0, 0}}});
    FAIL() << "a plan without an axis was drawn";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("axis"), std::string::npos) << e.what();
  }
  EXPECT_THROW(bm::MakePlanGlyphs({{"entry_mm", {0, 0, 0}}, {"axis", {0, 0, 0}}}),
               std::invalid_argument);
  EXPECT_THROW(
      bm::MakePlanGlyphs(
          {{"entry_mm", {0, 0, 0}}, {"axis", {0, 0, 1}}, {"landmarks", {{"trigonum_mm", {1, 2}}}}}),
      std::invalid_argument);
}
