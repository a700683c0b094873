// Template part of bmCTImage.h.
#pragma once

#include <algorithm>
#include <limits>

namespace bm {

template <class TImage>
Box3 WorldBoxOfRegion(const TImage* image, const typename TImage::RegionType& region) {
  Box3 b;
  b.lo = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  b.hi = {-b.lo[0], -b.lo[1], -b.lo[2]};
  const auto idx = region.GetIndex();
  const auto size = region.GetSize();
  for (int c = 0; c < 8; ++c) {
    itk::ContinuousIndex<double, 3> ci;
    for (int a = 0; a < 3; ++a)
      ci[a] = (c >> a & 1) ? double(idx[a]) + double(size[a]) - 0.5 : double(idx[a]) - 0.5;
    itk::Point<double, 3> p;
    image->TransformContinuousIndexToPhysicalPoint(ci, p);
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], p[a]);
      b.hi[a] = std::max(b.hi[a], p[a]);
    }
  }
  return b;
}

} // namespace bm
