// bmBoxROI.h - an oriented box region of interest: the bone inside a box of any orientation
// (around a glenoid whose face is oblique to the scanner's axes), as well as the axis-aligned
// "roi" box.
//
// The box: centre c (world mm), half sizes h (mm, along its own axes) and rotation angles
// (rx, ry, rz) in degrees: its axes are the columns of R = Rz(rz) Rx(rx) Ry(ry) (rotations about
// the world y, then x, then z axis: VTK's orientation order, that of vtkProp3D and of ParaView's
// box widget, so the box the 3D view shows is the box that is cut; all zero = axis-aligned). A
// world point p is inside when |R^T (p - c)|_a <= h_a on each axis a.
//
// In the CT chain (Docs/Segmentation.md) the CT is cropped to the box's axis-aligned bounds and
// the bone voxels whose centres lie outside the box are dropped right after the threshold, before
// the components, the separation and the cavity fill.
#pragma once

#include "bmMask.h"
#include "bmVoxmap.h" // bm::Box3

#include <array>
#include <string>

namespace bm {

struct OrientedBox {
  std::array<double, 3> centreMm{0, 0, 0};
  std::array<double, 3> halfSizesMm{0, 0, 0};
  /// Angles about world x, y, z (deg), applied y first, then x, then z (R = Rz Rx Ry).
  std::array<double, 3> rotationDeg{0, 0, 0};

  /// Throws std::runtime_error naming `what` when a half size is not > 0 or a value not finite.
  void Check(const std::string& what) const;
  /// The box's axes: columns of R (see above).
  std::array<std::array<double, 3>, 3> Axes() const;
  bool Contains(const std::array<double, 3>& pMm) const;
  /// The world-axis-aligned box (mm) around it.
  Box3 Bounds() const;
};

/// Zero the voxels of `mask` whose centres lie outside `box`; returns the voxels zeroed.
int64_t MaskOutsideBox(MaskImage* mask, const OrientedBox& box);

} // namespace bm
