#include "bmTiltedStack.h"

#include "bmCTReader.h" // CheckMemoryBudget

#include <itkLinearInterpolateImageFunction.h>
#include <itkResampleImageFilter.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace bm {

namespace {

using Vec = std::array<double, 3>;

Vec Column(const HUImage::DirectionType& d, int a) {
  return {d[0][a], d[1][a], d[2][a]};
}
double Dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec Cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec Normalised(Vec v) {
  const double n = std::sqrt(Dot(v, v));
  for (auto& x : v)
    x /= n;
  return v;
}

} // namespace

double StackTiltDeg(const HUImage* image) {
  const auto& d = image->GetDirection();
  const Vec n = Normalised(Cross(Column(d, 0), Column(d, 1)));
  const Vec k = Normalised(Column(d, 2));
  const double c = std::clamp(std::abs(Dot(n, k)), 0.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

HUImage::Pointer ResampleTiltedStack(const HUImage* image, float outside, uint64_t maxMemoryBytes,
                                     const Progress& progress) {
  const auto& dir = image->GetDirection();
  const auto sp = image->GetSpacing();
  const auto size = image->GetLargestPossibleRegion().GetSize();
  const Vec r = Normalised(Column(dir, 0)), c = Normalised(Column(dir, 1));
  Vec n = Normalised(Cross(r, c));
  Vec step = Column(dir, 2); // one slice to the next, mm
  for (auto& x : step)
    x *= sp[2];
  if (Dot(step, n) < 0)
    for (auto& x : n)
      x = -x;
  const double planeGap = Dot(step, n);

  // The stack's corners in the (r, c, n) frame at the first voxel; the new grid covers them, its
  // in-plane origin on the first slice's own grid so that the first slice is sampled unchanged.
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  for (int corner = 0; corner < 8; ++corner) {
    const double i = (corner & 1) ? double(size[0] - 1) : 0.0;
    const double j = (corner & 2) ? double(size[1] - 1) : 0.0;
    const double k = (corner & 4) ? double(size[2] - 1) : 0.0;
    Vec p;
    for (int a = 0; a < 3; ++a)
      p[size_t(a)] = i * sp[0] * r[size_t(a)] + j * sp[1] * c[size_t(a)] + k * step[size_t(a)];
    const double u = Dot(p, r), v = Dot(p, c);
    lo[0] = std::min(lo[0], u);
    hi[0] = std::max(hi[0], u);
    lo[1] = std::min(lo[1], v);
    hi[1] = std::max(hi[1], v);
  }
  HUImage::SizeType outSize;
  double start[2];
  for (int a = 0; a < 2; ++a) {
    const double first = std::floor(lo[a] / sp[unsigned(a)] + 1e-6);
    const double last = std::ceil(hi[a] / sp[unsigned(a)] - 1e-6);
    start[a] = first * sp[unsigned(a)];
    outSize[unsigned(a)] = size_t(last - first) + 1;
  }
  outSize[2] = size[2];
  const uint64_t outBytes = uint64_t(outSize[0]) * outSize[1] * outSize[2] * sizeof(float);
  const uint64_t inBytes = uint64_t(size[0]) * size[1] * size[2] * sizeof(float);
  CheckMemoryBudget(outBytes + inBytes, maxMemoryBytes,
                    "resampling the tilted slices onto a grid along their normal (" +
                        std::to_string(outSize[0]) + " x " + std::to_string(outSize[1]) + " x " +
                        std::to_string(outSize[2]) + " voxels, beside the " +
                        std::to_string(size[0]) + " x " + std::to_string(size[1]) + " x " +
                        std::to_string(size[2]) + " read)");

  HUImage::PointType origin = image->GetOrigin();
  for (int a = 0; a < 3; ++a)
    origin[unsigned(a)] += start[0] * r[size_t(a)] + start[1] * c[size_t(a)];
  HUImage::DirectionType outDir;
  for (int a = 0; a < 3; ++a) {
    outDir[unsigned(a)][0] = r[size_t(a)];
    outDir[unsigned(a)][1] = c[size_t(a)];
    outDir[unsigned(a)][2] = n[size_t(a)];
  }
  HUImage::SpacingType outSpacing;
  outSpacing[0] = sp[0];
  outSpacing[1] = sp[1];
  outSpacing[2] = planeGap;

  using Resample = itk::ResampleImageFilter<HUImage, HUImage>;
  auto resample = Resample::New();
  resample->SetInput(image);
  resample->SetInterpolator(itk::LinearInterpolateImageFunction<HUImage, double>::New());
  resample->SetOutputOrigin(origin);
  resample->SetOutputSpacing(outSpacing);
  resample->SetOutputDirection(outDir);
  resample->SetSize(outSize);
  resample->SetDefaultPixelValue(outside);
  RunFilter(resample, progress, "resampling the tilted slices");
  HUImage::Pointer out = resample->GetOutput();
  out->DisconnectPipeline();
  return out;
}

} // namespace bm
