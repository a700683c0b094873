// bmBoneFractionImage.cxx - see bmBoneFractionImage.h.
#include "bmBoneFractionImage.h"

#include <algorithm>

#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>

namespace bm {

BoneFractionImage::BoneFractionImage()
    : Image_(vtkSmartPointer<vtkImageData>::New()),
      Fraction_(vtkSmartPointer<vtkFloatArray>::New()) {
  Fraction_->SetName("BoneFraction");
  Image_->GetPointData()->SetScalars(Fraction_);
}

BoneFractionImage::~BoneFractionImage() = default;

vtkImageData* BoneFractionImage::GetOutput() const {
  return Image_;
}

void BoneFractionImage::Reset(const Voxmap& bone) {
  Dims_ = bone.Dims();
  Spacing_ = bone.Spacing();
  Origin_ = bone.Origin();
  Image_->SetDimensions(Dims_[0], Dims_[1], Dims_[2]);
  Image_->SetSpacing(Spacing_, Spacing_, Spacing_);
  Image_->SetOrigin(Origin_[0], Origin_[1], Origin_[2]);
  Fraction_->SetNumberOfTuples(bone.NumVoxels());
  SeenGen_.assign(size_t(bone.BrickDims()[0]) * bone.BrickDims()[1] * bone.BrickDims()[2], 0);
}

void BoneFractionImage::CopyBrick(const Voxmap& bone, int bi, int bj, int bk) {
  float* out = Fraction_->GetPointer(0);
  constexpr float kScale = 1.0f / float(Voxmap::kFull); // a power of two: exact
  const int i0 = bi * Voxmap::kBrick, i1 = std::min(i0 + Voxmap::kBrick, Dims_[0]);
  const int j0 = bj * Voxmap::kBrick, j1 = std::min(j0 + Voxmap::kBrick, Dims_[1]);
  const int k0 = bk * Voxmap::kBrick, k1 = std::min(k0 + Voxmap::kBrick, Dims_[2]);
  for (int k = k0; k < k1; ++k)
    for (int j = j0; j < j1; ++j) {
      // The image's rows are dense, the voxmap's padded (Voxmap::Pitch).
      const int64_t row = bone.Index(0, j, k);
      float* outRow = out + int64_t(Dims_[0]) * (j + int64_t(Dims_[1]) * k);
      for (int i = i0; i < i1; ++i) {
        const Voxmap::Fill f = bone.LoadFill(row + i);
        outRow[i] = f <= 0 ? 0.0f : float(f) * kScale;
      }
    }
}

int64_t BoneFractionImage::Update(const Voxmap& bone) {
  const bool all = bone.Dims() != Dims_ || bone.Spacing() != Spacing_ || bone.Origin() != Origin_ ||
                   SeenGen_.empty();
  if (all)
    Reset(bone);
  const auto& bd = bone.BrickDims();
  int64_t copied = 0, b = 0;
  for (int bk = 0; bk < bd[2]; ++bk)
    for (int bj = 0; bj < bd[1]; ++bj)
      for (int bi = 0; bi < bd[0]; ++bi, ++b) {
        // Seen before the fills are read: a cut after this load moves the generation again.
        const uint32_t g = bone.SeenBrickGeneration(b);
        if (!all && g == SeenGen_[size_t(b)])
          continue;
        SeenGen_[size_t(b)] = g;
        CopyBrick(bone, bi, bj, bk);
        ++copied;
      }
  if (copied > 0) {
    Fraction_->Modified();
    Image_->Modified();
  }
  return copied;
}

} // namespace bm
