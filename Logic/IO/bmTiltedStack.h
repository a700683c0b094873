// bmTiltedStack.h - a slice stack whose slices do not lie straight above one another (a CT taken
// with gantry tilt, or slice positions sheared in the slice plane), brought onto a grid along the
// slice normal.
//
// A DICOM series gives each slice's plane (ImageOrientationPatient) and position
// (ImagePositionPatient). With gantry tilt the positions move along the table, not along the
// slices' normal: voxel (i, j, k) lies at origin + i sx r + j sy c + k d, where r and c are the
// row and column directions, sx and sy the pixel spacing and d the step between slice positions,
// which is not parallel to the normal n = r x c. The reader builds the image with that geometry
// (direction columns r, c and d/|d|, spacing sx, sy and |d|), and ResampleTiltedStack turns it
// into an image with an orthogonal grid (direction r, c, n; spacing sx, sy and d . n, the
// distance between slice planes) that holds every voxel of the stack, sampled at the same world
// positions by linear interpolation (ITK's ResampleImageFilter), so every bone keeps its place.
#pragma once

#include "bmCTImage.h"
#include "bmProgress.h"

#include <cstdint>

namespace bm {

/// Angle, degrees, between the image's third axis and the normal of its first two (0 for an
/// orthogonal grid; the gantry tilt of a tilted stack).
double StackTiltDeg(const HUImage* image);

/// The tilted stack `image` (first two axes orthonormal, third axis at StackTiltDeg from their
/// normal) on the orthogonal grid described above: the same in-plane axes and spacing, the third
/// axis the slice normal with spacing = the distance between slice planes (mm), the same slice
/// planes; voxels of the new grid outside the stack get `outside` (the caller passes the lowest
/// value of the CT, air). The new image's bytes plus the stack's are checked against
/// maxMemoryBytes (0 = DefaultMemoryLimit()) before it is allocated. Throws std::runtime_error
/// when the budget is exceeded.
HUImage::Pointer ResampleTiltedStack(const HUImage* image, float outside, uint64_t maxMemoryBytes,
                                     const Progress& progress = {});

} // namespace bm
