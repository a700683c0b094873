// bmBoneSurface.cxx - see bmBoneSurface.h.
#include "bmBoneSurface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <vtkAppendPolyData.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

namespace bm {

// The padded lattice: sample p = i + 1 for voxel i, plus one void sample before and after the
// grid on each axis, so there are Dims + 2 samples and Dims + 1 cells per axis.

BoneSurface::BoneSurface(int brickVoxels, double iso)
    : Brick_(brickVoxels), Iso_(iso), Output_(vtkSmartPointer<vtkPolyData>::New()) {
  if (brickVoxels < 2)
    throw std::invalid_argument("BoneSurface: brickVoxels must be >= 2");
  if (!(iso > 0.0 && iso < 1.0))
    throw std::invalid_argument("BoneSurface: iso must be in (0, 1)");
}

BoneSurface::~BoneSurface() = default;

vtkPolyData* BoneSurface::GetOutput() const {
  return Output_;
}

void BoneSurface::MarkAllDirty() {
  AllDirty_ = true;
}

void BoneSurface::MarkDirty(const Box3& box) {
  if (AllDirty_ || Spacing_ <= 0)
    return; // everything is extracted next time anyway
  for (int a = 0; a < 3; ++a)
    if (box.hi[a] < box.lo[a])
      return;
  std::array<int, 3> lo, hi;
  for (int a = 0; a < 3; ++a) {
    // Padded sample index of the box's ends, widened by one sample for the gradient stencil.
    const double plo = (box.lo[a] - Origin_[a]) / Spacing_ + 1.0;
    const double phi = (box.hi[a] - Origin_[a]) / Spacing_ + 1.0;
    const double cells = double(Dims_[a]) + 1.0;
    const int slo = int(std::floor(std::clamp(plo, 0.0, cells))) - 1;
    const int shi = int(std::ceil(std::clamp(phi, 0.0, cells))) + 1;
    // A sample on a brick boundary belongs to both bricks that share it.
    lo[a] = std::clamp((slo - 1) / Brick_, 0, BrickDims_[a] - 1);
    hi[a] = std::clamp(shi / Brick_, 0, BrickDims_[a] - 1);
  }
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i)
        Dirty_[size_t(i + int64_t(BrickDims_[0]) * (j + int64_t(BrickDims_[1]) * k))] = 1;
}

void BoneSurface::Reset(const Voxmap& bone) {
  Dims_ = bone.Dims();
  Spacing_ = bone.Spacing();
  Origin_ = bone.Origin();
  for (int a = 0; a < 3; ++a)
    BrickDims_[a] = (Dims_[a] + 1 + Brick_ - 1) / Brick_;
  Bricks_.assign(size_t(NumBricks()), nullptr);
  Dirty_.assign(size_t(NumBricks()), 1);
  AllDirty_ = false;
}

vtkSmartPointer<vtkPolyData> BoneSurface::ExtractBrick(const Voxmap& bone, int bi, int bj,
                                                       int bk) const {
  const std::array<int, 3> b{bi, bj, bk};
  std::array<int, 3> p0, n;
  for (int a = 0; a < 3; ++a) {
    p0[a] = b[a] * Brick_;
    n[a] = std::min(p0[a] + Brick_, Dims_[a] + 1) - p0[a] + 1; // samples, shared planes included
  }
  vtkNew<vtkFloatArray> values;
  values->SetName("BoneFraction");
  values->SetNumberOfValues(vtkIdType(n[0]) * n[1] * n[2]);
  float* v = values->GetPointer(0);
  float lo = 1.0f, hi = 0.0f;
  for (int k = 0; k < n[2]; ++k) {
    const int gk = p0[2] + k - 1;
    for (int j = 0; j < n[1]; ++j) {
      const int gj = p0[1] + j - 1;
      for (int i = 0; i < n[0]; ++i) {
        const int gi = p0[0] + i - 1;
        const float f =
            bone.Contains(gi, gj, gk) ? float(bone.Fraction(bone.Index(gi, gj, gk))) : 0.0f;
        *v++ = f;
        lo = std::min(lo, f);
        hi = std::max(hi, f);
      }
    }
  }
  if (hi < Iso_ || lo >= Iso_)
    return nullptr; // all void or all bone: no surface in this brick

  vtkNew<vtkImageData> image;
  image->SetDimensions(n[0], n[1], n[2]);
  image->SetSpacing(Spacing_, Spacing_, Spacing_);
  image->SetOrigin(Origin_[0] + (p0[0] - 1) * Spacing_, Origin_[1] + (p0[1] - 1) * Spacing_,
                   Origin_[2] + (p0[2] - 1) * Spacing_);
  image->GetPointData()->SetScalars(values);

  vtkNew<vtkFlyingEdges3D> edges;
  edges->SetInputData(image);
  edges->SetValue(0, Iso_);
  edges->ComputeNormalsOn();
  edges->ComputeGradientsOff();
  edges->ComputeScalarsOff();
  edges->Update();
  vtkPolyData* out = edges->GetOutput();
  if (out->GetNumberOfCells() == 0)
    return nullptr;
  vtkSmartPointer<vtkPolyData> brick = vtkSmartPointer<vtkPolyData>::New();
  brick->ShallowCopy(out);
  return brick;
}

int BoneSurface::Update(const Voxmap& bone) {
  if (AllDirty_ || bone.Dims() != Dims_ || bone.Spacing() != Spacing_ || bone.Origin() != Origin_)
    Reset(bone);
  int extracted = 0;
  for (int k = 0; k < BrickDims_[2]; ++k)
    for (int j = 0; j < BrickDims_[1]; ++j)
      for (int i = 0; i < BrickDims_[0]; ++i) {
        const size_t b = size_t(i + int64_t(BrickDims_[0]) * (j + int64_t(BrickDims_[1]) * k));
        if (!Dirty_[b])
          continue;
        Bricks_[b] = ExtractBrick(bone, i, j, k);
        Dirty_[b] = 0;
        ++extracted;
      }
  if (extracted == 0 && Output_->GetNumberOfPoints() > 0)
    return 0;
  vtkNew<vtkAppendPolyData> append;
  for (const auto& brick : Bricks_)
    if (brick)
      append->AddInputData(brick);
  if (append->GetNumberOfInputConnections(0) == 0) {
    Output_->Initialize();
  } else {
    append->Update();
    Output_->ShallowCopy(append->GetOutput());
  }
  Output_->Modified();
  return extracted;
}

} // namespace bm
