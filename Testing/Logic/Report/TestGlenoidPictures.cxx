// The plan's pictures of the glenoid (bmGlenoidPictures.h): before and after are written, the
// planned axis is drawn in red where the camera looks down it, the cut shows as a difference
// between the two pictures, and a plan without an axis is refused by name.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include "bmGlenoidPictures.h"
#include "bmVoxmap.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace {

namespace fs = std::filesystem;

vtkSmartPointer<vtkImageData> ReadPng(const fs::path& file) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  return reader->GetOutput();
}

/// Pixels for which `is(r, g, b)` holds (shading darkens the drawn colours, so hues are tested).
template <class Pred> int CountPixels(vtkImageData* image, Pred is) {
  auto* px = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  int n = 0;
  for (vtkIdType i = 0; i < px->GetNumberOfTuples(); ++i)
    n += is(int(px->GetValue(3 * i)), int(px->GetValue(3 * i + 1)), int(px->GetValue(3 * i + 2)));
  return n;
}

bool Red(int r, int g, int b) {
  return r > 90 && 2 * g < r && 2 * b < r;
}
bool Yellow(int r, int g, int b) {
  return r > 120 && g > 100 && 2 * b < g;
}
// The bone is ivory (237, 227, 199): white has no blue deficit.
bool White(int r, int g, int b) {
  return std::min({r, g, b}) > 215 && std::abs(r - b) < 20;
}

} // namespace

TEST(GlenoidPictures, BeforeAndAfterWithThePlanDrawn) {
  // A 30 x 30 x 10 mm slab of bone, top face at z = 0; "after": a 6 mm deep, 8 mm radius pocket
  // under the entry.
  bm::Voxmap before({40, 40, 20}, 1.0, {-20, -20, -15});
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) {
        const double x = -20 + i + 0.5, y = -20 + j + 0.5, z = -15 + k + 0.5;
        if (std::abs(x) < 15 && std::abs(y) < 15 && z > -10 && z < 0)
          before.SetFill(before.Index(i, j, k), bm::Voxmap::kFull);
      }
  bm::Voxmap after = before;
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) {
        const double x = -20 + i + 0.5, y = -20 + j + 0.5, z = -15 + k + 0.5;
        if (x * x + y * y < 64 && z > -6)
          after.SetFill(after.Index(i, j, k), 0);
      }
  const nlohmann::json planning = {
      {"entry_mm", {0, 0, 0}},
      {"axis", {0, 0, 1}},
      {"reamer_diameter_mm", 20},
      {"landmarks",
       {{"face_normal", {0.2, 0, 1}}, {"rim_mm", {{-12, -12, 0}, {12, -12, 0}, {12, 12, 0}}}}}};
  const fs::path dir = fs::path(testing::TempDir()) / "bm-glenoid-pictures";
  fs::remove_all(dir);
  const bm::GlenoidPictureFiles files =
      bm::WriteGlenoidPictures(dir.string(), before, after, planning, 300);
  ASSERT_TRUE(fs::exists(dir / files.before));
  ASSERT_TRUE(fs::exists(dir / files.after));
  auto b = ReadPng(dir / files.before), a = ReadPng(dir / files.after);
  int dims[3];
  b->GetDimensions(dims);
  EXPECT_EQ(dims[0], 300);
  EXPECT_GT(CountPixels(b, Red), 50) << "the red axis is not drawn";
  EXPECT_GT(CountPixels(b, White), 50) << "the white face-plane circle is not drawn";
  EXPECT_GT(CountPixels(b, Yellow), 50) << "the yellow rim is not drawn";
  // The pocket changes the picture.
  auto* pb = vtkUnsignedCharArray::SafeDownCast(b->GetPointData()->GetScalars());
  auto* pa = vtkUnsignedCharArray::SafeDownCast(a->GetPointData()->GetScalars());
  int differing = 0;
  for (vtkIdType i = 0; i < pb->GetNumberOfValues(); ++i)
    differing += pb->GetValue(i) != pa->GetValue(i);
  EXPECT_GT(differing, 1000);
  fs::remove_all(dir);

  EXPECT_THROW(bm::WriteGlenoidPictures(dir.string(), before, after, {{"entry_mm", {0, 0, 0}}}),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / files.before));
}
