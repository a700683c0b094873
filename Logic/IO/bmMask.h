// bmMask.h - binary bone masks at CT resolution and their connected components, the common
// currency of the segmentation stages (bmBoneSegmenter -> bmBoneSeparation -> bmCavityFill).
//
// A mask holds 0 (not bone) or a non-zero mark per CT voxel on the CT's own grid (same region,
// spacing, origin and direction as the HU image). World points are mm in the CT's frame.
#pragma once

#include "bmProgress.h"

#include <itkImage.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bm {

using MaskImage = itk::Image<uint8_t, 3>;
using LabelImage = itk::Image<uint32_t, 3>;

/// Connected components of the non-zero voxels of `mask` (itk::ConnectedComponentImageFilter,
/// 26-connected when fullyConnected, else 6-connected), relabelled 1..n by decreasing size
/// (itk::RelabelComponentImageFilter); sizes[l - 1] = voxels of label l. `stage` names the
/// progress stage and the error prefix.
LabelImage::Pointer LabelComponents(const MaskImage* mask, bool fullyConnected,
                                    std::vector<itk::SizeValueType>& sizes,
                                    const Progress& progress, const std::string& stage);

/// Index (i, j, k) of the voxel of `image` holding world point p (mm), relative to the start of
/// its largest region; nullopt when p lies outside the image.
template <class TImage>
std::optional<std::array<int, 3>> VoxelOfPoint(const TImage* image, const std::array<double, 3>& p);

/// The non-zero label nearest to voxel ijk (mm, through the spacing) within `radius` voxels
/// (a cube), 0 when none.
uint32_t NearestLabel(const LabelImage* labels, const std::array<int, 3>& ijk, int radius);

/// "(x, y, z) mm".
std::string FormatPointMm(const std::array<double, 3>& p);

template <class TImage>
std::optional<std::array<int, 3>> VoxelOfPoint(const TImage* image,
                                               const std::array<double, 3>& p) {
  const auto region = image->GetLargestPossibleRegion();
  itk::Point<double, 3> q;
  for (int a = 0; a < 3; ++a)
    q[a] = p[a];
  itk::ContinuousIndex<double, 3> ci;
  image->TransformPhysicalPointToContinuousIndex(q, ci);
  std::array<int, 3> out{};
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor(ci[a] + 0.5) - double(region.GetIndex(a));
    if (!(f >= 0 && f < double(region.GetSize(a))))
      return std::nullopt;
    out[a] = int(f);
  }
  return out;
}

} // namespace bm
