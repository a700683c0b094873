// The picture of a plan that found no glenoid (bmFailurePicture.h): the bone from the front with
// the named joints marked in yellow, two marks of one joint sharing a sphere; a bone with no
// surface refused by name, nothing written.
#include "bmFailurePicture.h"
#include "bmVoxmap.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <filesystem>

namespace {

int YellowPixels(const std::filesystem::path& file) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(file.string().c_str());
  reader->Update();
  auto* px = vtkUnsignedCharArray::SafeDownCast(reader->GetOutput()->GetPointData()->GetScalars());
  int n = 0;
  for (vtkIdType i = 0; i < px->GetNumberOfTuples(); ++i) {
    const int r = px->GetValue(3 * i), g = px->GetValue(3 * i + 1), b = px->GetValue(3 * i + 2);
    n += r > 120 && g > 90 && 3 * b < g; // shading darkens the yellow, the ivory bone has blue
  }
  return n;
}

} // namespace

TEST(FailurePicture, TheBoneFromTheFrontWithTheJointsMarked) {
  // A 30 mm cube of bone; two marks of one joint on its front face, one on its top.
  bm::Voxmap bone({40, 40, 40}, 1.0, {-20, -20, -20});
  for (int k = 5; k < 35; ++k)
    for (int j = 5; j < 35; ++j)
      for (int i = 5; i < 35; ++i)
        bone.SetFill(bone.Index(i, j, k), bm::Voxmap::kFull);
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "bm-failure-picture";
  fs::remove_all(dir);
  fs::create_directories(dir);
  bm::WriteFailurePicture((dir / "none.png").string(), bone, {}, 200);
  bm::WriteFailurePicture((dir / "marked.png").string(), bone,
                          {{0, -15, 0}, {0.5, -15, 0.5}, {0, 0, 15}}, 200);
  EXPECT_EQ(YellowPixels(dir / "none.png"), 0);
  EXPECT_GT(YellowPixels(dir / "marked.png"), 100);

  const bm::Voxmap empty({8, 8, 8}, 1.0, {0, 0, 0});
  EXPECT_THROW(bm::WriteFailurePicture((dir / "empty.png").string(), empty, {}),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "empty.png"));
  fs::remove_all(dir);
}
