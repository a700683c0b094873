// bm::BoneFractionImage: the session's volume output, brought up to date per changed brick, is
// always the voxmap's fill fractions, and copies only the bricks that changed.
#include "bmBoneFractionImage.h"

#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>

namespace {

bm::Voxmap Ball() {
  bm::Voxmap v({30, 20, 17}, 0.25, {1.0, -2.0, 0.5});
  for (int k = 0; k < 17; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 30; ++i) {
        const double r2 = (i - 14.5) * (i - 14.5) + (j - 9.5) * (j - 9.5) + (k - 8.0) * (k - 8.0);
        if (r2 < 64)
          v.SetFill(v.Index(i, j, k), bm::Voxmap::Fill(bm::Voxmap::kFull * (1.0 - r2 / 128)));
      }
  return v;
}

void ExpectSameAsVoxmap(const bm::BoneFractionImage& image, const bm::Voxmap& v) {
  vtkImageData* out = image.GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  ASSERT_EQ(dims[0], v.Dims()[0]);
  ASSERT_EQ(dims[1], v.Dims()[1]);
  ASSERT_EQ(dims[2], v.Dims()[2]);
  EXPECT_DOUBLE_EQ(out->GetSpacing()[0], v.Spacing());
  EXPECT_DOUBLE_EQ(out->GetOrigin()[1], v.Origin()[1]);
  vtkDataArray* f = out->GetPointData()->GetArray("BoneFraction");
  ASSERT_NE(f, nullptr);
  int64_t i = 0; // the image's voxels in order; the voxmap's rows are padded (Voxmap::Pitch)
  for (int z = 0; z < dims[2]; ++z)
    for (int y = 0; y < dims[1]; ++y)
      for (int x = 0; x < dims[0]; ++x, ++i)
        ASSERT_FLOAT_EQ(float(f->GetTuple1(i)), float(v.Fraction(v.Index(x, y, z))))
            << "voxel " << x << " " << y << " " << z;
}

} // namespace

TEST(BoneFractionImage, CopiesOnlyTheChangedBricksAndStaysEqualToTheVoxmap) {
  bm::Voxmap v = Ball();
  bm::BoneFractionImage image;
  const int64_t bricks = int64_t(v.BrickDims()[0]) * v.BrickDims()[1] * v.BrickDims()[2];
  EXPECT_EQ(image.Update(v), bricks); // the first update copies everything
  ExpectSameAsVoxmap(image, v);
  EXPECT_EQ(image.Update(v), 0); // nothing changed
  const vtkMTimeType before = image.GetOutput()->GetPointData()->GetArray(0)->GetMTime();

  // Cut two voxels in two bricks, and one void voxel (no change a reader sees).
  bool voided = false;
  v.Remove(v.Index(14, 9, 8), bm::Voxmap::kFull / 2, voided);
  v.Remove(v.Index(20, 12, 9), bm::Voxmap::kFull, voided);
  v.Remove(v.Index(0, 0, 0), bm::Voxmap::kFull, voided);
  EXPECT_EQ(image.Update(v), 2);
  EXPECT_GT(image.GetOutput()->GetPointData()->GetArray(0)->GetMTime(), before);
  ExpectSameAsVoxmap(image, v);

  // A new grid is copied whole.
  bm::Voxmap w({9, 9, 9}, 0.5, {0, 0, 0});
  w.SetFill(w.Index(4, 4, 4), bm::Voxmap::kFull);
  EXPECT_EQ(image.Update(w), 8);
  ExpectSameAsVoxmap(image, w);
}

TEST(BoneFractionImage, AnotherVoxmapOfTheSameGridIsCopiedWholeAfterMarkAllDirty) {
  // A new session's voxmap has the same grid and generations that may equal the ones this image
  // kept from the last one: without MarkAllDirty() nothing would be copied.
  bm::Voxmap first = Ball();
  bm::BoneFractionImage image;
  image.Update(first);
  bm::Voxmap second = Ball();
  bool voided = false;
  second.Remove(second.Index(14, 9, 8), bm::Voxmap::kFull, voided);
  image.MarkAllDirty();
  const int64_t bricks =
      int64_t(second.BrickDims()[0]) * second.BrickDims()[1] * second.BrickDims()[2];
  EXPECT_EQ(image.Update(second), bricks);
  ExpectSameAsVoxmap(image, second);
}
