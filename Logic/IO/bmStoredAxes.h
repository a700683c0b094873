// bmStoredAxes.h - a CT stored along other axes than the patient's: the voxel grid's i, j, k
// running along any order of the world's x, y, z, each either way, with the direction cosines
// that say so, as scanners and exports store them (superior toward low slice indices, a sagittal
// or coronal stack). The world positions of the voxels do not change: a reader that applies the
// direction sees the same CT. The test scans carry it (`bmsim phantom scapula --axes`).
#pragma once

#include "bmCTImage.h"

#include <array>
#include <string>

namespace bm {

/// For each stored axis (i, j, k): the world axis it runs along (0 = x, 1 = y, 2 = z) and
/// whether it runs against it.
struct StoredAxes {
  std::array<int, 3> world{0, 1, 2};
  std::array<bool, 3> reversed{false, false, false};
};

/// Parses "X,Y,Z" in any order, each optionally prefixed with '-' ("x,-z,y": i along x, j
/// against z, k along y). Throws std::invalid_argument naming the text when it is not a
/// permutation of x, y and z.
StoredAxes ParseStoredAxes(const std::string& text);

/// `ct` (axial, identity direction) stored along `axes`: the voxels permuted and flipped, the
/// spacing permuted, the origin and direction set so that every voxel keeps its world position.
CTImage StoreAlongAxes(const CTImage& ct, const StoredAxes& axes);

} // namespace bm
