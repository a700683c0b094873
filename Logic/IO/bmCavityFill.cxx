#include "bmCavityFill.h"

#include <itkBinaryFillholeImageFilter.h>
#include <itkBinaryMorphologicalClosingImageFilter.h>
#include <itkFlatStructuringElement.h>
#include <itkSliceBySliceImageFilter.h>

#include <vector>

namespace bm {

namespace {

/// Step 5: O holds each original bone voxel's bone label (0 elsewhere); the voxels of M that are
/// not in O were added. Each 6-connected region of added voxels that touches two or more bones
/// (a joint space the closing enclosed, and the bridges that enclosed it) is taken out of M.
void KeepBonesApart(uint8_t* M, const uint32_t* O, int nx, int ny, int nz, CavityFillResult& res) {
  const int64_t n = int64_t(nx) * ny * nz;
  const int64_t step[3] = {1, nx, int64_t(nx) * ny};
  auto neighbours = [&](int64_t v, auto&& f) {
    const int64_t i = v % nx, j = (v / nx) % ny, k = v / (int64_t(nx) * ny);
    const int64_t c[3] = {i, j, k}, size[3] = {nx, ny, nz};
    for (int a = 0; a < 3; ++a) {
      if (c[a] > 0)
        f(v - step[a]);
      if (c[a] + 1 < size[a])
        f(v + step[a]);
    }
  };
  std::vector<uint8_t> seen(size_t(n), 0);
  std::vector<int64_t> region;
  for (int64_t s = 0; s < n; ++s) {
    if (!M[s] || O[s] || seen[size_t(s)])
      continue;
    // One region of added voxels, and the bones it touches.
    region.assign(1, s);
    seen[size_t(s)] = 1;
    uint32_t first = 0;
    bool several = false;
    for (size_t q = 0; q < region.size(); ++q)
      neighbours(region[q], [&](int64_t u) {
        if (O[u]) {
          several |= first && O[u] != first;
          if (!first)
            first = O[u];
        } else if (M[u] && !seen[size_t(u)]) {
          seen[size_t(u)] = 1;
          region.push_back(u);
        }
      });
    if (!several)
      continue;
    for (const int64_t v : region) {
      (M[v] == kFilled ? res.filledVoxels : res.closedVoxels) -= 1;
      M[v] = kNotBone;
      ++res.apartVoxels;
    }
  }
}

} // namespace

CavityFillResult FillCavities(MaskImage* mask, const HUImage* hu, const CavityFillOptions& opt,
                              const Progress& progress) {
  CavityFillResult res;
  if (!opt.fill)
    return res;
  const auto region = mask->GetLargestPossibleRegion();
  const int nx = int(region.GetSize(0)), ny = int(region.GetSize(1)), nz = int(region.GetSize(2));
  const int64_t n = int64_t(region.GetNumberOfPixels());
  const auto sp = mask->GetSpacing();
  const double voxelVolume = sp[0] * sp[1] * sp[2];
  uint8_t* M = mask->GetBufferPointer();
  const float* H = hu->GetBufferPointer();

  // Binary copy (1 = bone) for the ITK filters.
  auto bone = MaskImage::New();
  bone->CopyInformation(mask);
  bone->SetRegions(region);
  bone->Allocate();
  uint8_t* B = bone->GetBufferPointer();
  for (int64_t v = 0; v < n; ++v)
    B[v] = M[v] ? 1 : 0;
  // The bones before anything is added (step 5).
  LabelImage::Pointer bones;
  if (opt.keepBonesApart) {
    std::vector<itk::SizeValueType> boneSizes;
    bones = LabelComponents(bone, true, boneSizes, Progress(), "filling cavities: bones");
    if (boneSizes.size() < 2)
      bones = nullptr; // one bone: nothing to keep apart
  }

  // 1. Closing.
  if (opt.closingRadiusVoxels > 0) {
    using Ball = itk::FlatStructuringElement<3>;
    Ball::RadiusType radius;
    radius.Fill(itk::SizeValueType(opt.closingRadiusVoxels));
    auto closing = itk::BinaryMorphologicalClosingImageFilter<MaskImage, MaskImage, Ball>::New();
    closing->SetInput(bone);
    closing->SetKernel(Ball::Ball(radius));
    closing->SetForegroundValue(1);
    closing->SetSafeBorder(true);
    RunFilter(closing, progress.Range(0, 0.25), "filling cavities: closing");
    const uint8_t* C = closing->GetOutput()->GetBufferPointer();
    for (int64_t v = 0; v < n; ++v)
      if (C[v] && !M[v]) {
        M[v] = kBone;
        B[v] = 1;
        ++res.closedVoxels;
      }
  }

  // 2. Background components.
  auto background = MaskImage::New();
  background->CopyInformation(mask);
  background->SetRegions(region);
  background->Allocate();
  uint8_t* G = background->GetBufferPointer();
  for (int64_t v = 0; v < n; ++v)
    G[v] = B[v] ? 0 : 1;
  std::vector<itk::SizeValueType> sizes;
  LabelImage::Pointer holes = LabelComponents(background, false, sizes, progress.Range(0.25, 0.5),
                                              "filling cavities: components");
  background = nullptr;
  const uint32_t* L = holes->GetBufferPointer();
  const size_t nl = sizes.size() + 1;
  std::vector<uint8_t> touches(nl, 0);
  std::vector<double> sumHU(nl, 0.0);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int64_t v = i + int64_t(nx) * (j + int64_t(ny) * k);
        const uint32_t l = L[v];
        if (!l)
          continue;
        sumHU[l] += H[v];
        if (i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1)
          touches[l] = 1;
      }
  // The surroundings: the largest background component at the border.
  uint32_t outside = 0;
  for (uint32_t l = 1; l < nl && !outside; ++l)
    if (touches[l])
      outside = l;

  // 3. Slice-wise holes, counted per border-touching component.
  std::vector<int64_t> inSliceHoles(nl, 0);
  bool anyBorderCandidate = false;
  for (uint32_t l = 1; l < nl; ++l)
    anyBorderCandidate |= touches[l] && l != outside;
  if (anyBorderCandidate) {
    std::vector<uint8_t> sliceHole(size_t(n), 0);
    using Slice = itk::Image<uint8_t, 2>;
    for (unsigned d = 0; d < 3; ++d) {
      auto fill2d = itk::BinaryFillholeImageFilter<Slice>::New();
      fill2d->SetForegroundValue(1);
      fill2d->SetFullyConnected(false);
      auto sbs = itk::SliceBySliceImageFilter<MaskImage, MaskImage>::New();
      sbs->SetInput(bone);
      sbs->SetFilter(fill2d);
      sbs->SetDimension(d);
      RunFilter(sbs, progress.Range(0.5 + 0.13 * d, 0.5 + 0.13 * (d + 1)),
                "filling cavities: slice-wise holes");
      const uint8_t* F = sbs->GetOutput()->GetBufferPointer();
      for (int64_t v = 0; v < n; ++v)
        if (F[v] && !B[v])
          sliceHole[size_t(v)] = 1;
    }
    for (int64_t v = 0; v < n; ++v)
      if (sliceHole[size_t(v)] && L[v])
        ++inSliceHoles[L[v]];
  }

  // 4. Fill.
  std::vector<uint8_t> fill(nl, 0);
  for (uint32_t l = 1; l < nl; ++l) {
    const double count = double(sizes[l - 1]);
    if (l == outside || count * voxelVolume > opt.maxHoleVolumeMm3 ||
        sumHU[l] / count < opt.holeMinMeanHU || sumHU[l] / count >= opt.holeMaxMeanHU)
      continue;
    if (touches[l] && 2 * inSliceHoles[l] < int64_t(count))
      continue;
    fill[l] = 1;
    ++res.holesFilled;
    res.borderHolesFilled += touches[l];
  }
  for (int64_t v = 0; v < n; ++v)
    if (L[v] && fill[L[v]]) {
      M[v] = kFilled;
      ++res.filledVoxels;
    }
  if (bones)
    KeepBonesApart(M, bones->GetBufferPointer(), nx, ny, nz, res);
  progress(1.0, "filling cavities");
  return res;
}

} // namespace bm
