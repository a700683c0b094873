#include "bmCTImage.h"

namespace bm {

std::array<int, 3> CTImage::Size() const {
  auto s = hu->GetLargestPossibleRegion().GetSize();
  return {int(s[0]), int(s[1]), int(s[2])};
}

std::array<double, 3> CTImage::Spacing() const {
  auto s = hu->GetSpacing();
  return {s[0], s[1], s[2]};
}

Box3 CTImage::WorldBounds() const {
  return WorldBoxOfRegion(hu.GetPointer(), hu->GetLargestPossibleRegion());
}

uint64_t CTImage::Bytes() const {
  return uint64_t(hu->GetLargestPossibleRegion().GetNumberOfPixels()) * sizeof(float);
}

} // namespace bm
