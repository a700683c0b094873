#include "bmBoxROI.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace bm {

void OrientedBox::Check(const std::string& what) const {
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(centreMm[a]) || !std::isfinite(halfSizesMm[a]) ||
        !std::isfinite(rotationDeg[a]))
      throw std::runtime_error(what + " holds a value that is not a finite number");
    if (!(halfSizesMm[a] > 0))
      throw std::runtime_error(
          what + ": the half sizes must be > 0 mm (got " + std::to_string(halfSizesMm[0]) + ", " +
          std::to_string(halfSizesMm[1]) + ", " + std::to_string(halfSizesMm[2]) + ")");
  }
}

std::array<std::array<double, 3>, 3> OrientedBox::Axes() const {
  const double k = std::numbers::pi / 180.0;
  const double cx = std::cos(rotationDeg[0] * k), sx = std::sin(rotationDeg[0] * k);
  const double cy = std::cos(rotationDeg[1] * k), sy = std::sin(rotationDeg[1] * k);
  const double cz = std::cos(rotationDeg[2] * k), sz = std::sin(rotationDeg[2] * k);
  // R = Rz Rx Ry, row-major (VTK's orientation order: vtkTransform RotateZ, RotateX, RotateY).
  const double R[3][3] = {{cz * cy - sz * sx * sy, -sz * cx, cz * sy + sz * sx * cy},
                          {sz * cy + cz * sx * sy, cz * cx, sz * sy - cz * sx * cy},
                          {-cx * sy, sx, cx * cy}};
  std::array<std::array<double, 3>, 3> axes{};
  for (int a = 0; a < 3; ++a)
    for (int r = 0; r < 3; ++r)
      axes[a][r] = R[r][a];
  return axes;
}

bool OrientedBox::Contains(const std::array<double, 3>& p) const {
  const auto axes = Axes();
  for (int a = 0; a < 3; ++a) {
    double u = 0;
    for (int r = 0; r < 3; ++r)
      u += axes[a][r] * (p[r] - centreMm[r]);
    if (std::abs(u) > halfSizesMm[a])
      return false;
  }
  return true;
}

Box3 OrientedBox::Bounds() const {
  const auto axes = Axes();
  Box3 b;
  for (int r = 0; r < 3; ++r) {
    double extent = 0;
    for (int a = 0; a < 3; ++a)
      extent += std::abs(axes[a][r]) * halfSizesMm[a];
    b.lo[r] = centreMm[r] - extent;
    b.hi[r] = centreMm[r] + extent;
  }
  return b;
}

int64_t MaskOutsideBox(MaskImage* mask, const OrientedBox& box) {
  const auto region = mask->GetLargestPossibleRegion();
  const int nx = int(region.GetSize(0)), ny = int(region.GetSize(1)), nz = int(region.GetSize(2));
  uint8_t* M = mask->GetBufferPointer();
  int64_t zeroed = 0;
  MaskImage::IndexType index;
  itk::Point<double, 3> p;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int64_t v = i + int64_t(nx) * (j + int64_t(ny) * k);
        if (!M[v])
          continue;
        index[0] = region.GetIndex(0) + i;
        index[1] = region.GetIndex(1) + j;
        index[2] = region.GetIndex(2) + k;
        mask->TransformIndexToPhysicalPoint(index, p);
        if (!box.Contains({p[0], p[1], p[2]})) {
          M[v] = 0;
          ++zeroed;
        }
      }
  return zeroed;
}

} // namespace bm
