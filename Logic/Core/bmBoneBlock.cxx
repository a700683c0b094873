#include "bmBoneBlock.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bm {

Voxmap MakeBoneBlock(const std::array<double, 3>& sizeMm, int resolution, float material) {
  if (resolution < 1)
    throw std::invalid_argument("block resolution must be >= 1");
  const double h = std::max({sizeMm[0], sizeMm[1], sizeMm[2]}) / resolution;
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a)
    dims[a] = std::max(1, int(std::lround(sizeMm[a] / h)));
  // Voxel centres: the block spans [-x/2, x/2] x [-y/2, y/2] x [-z, 0] (faces on voxel faces,
  // extents rounded to whole voxels).
  Voxmap v(dims, h,
           {-0.5 * dims[0] * h + 0.5 * h, -0.5 * dims[1] * h + 0.5 * h, -dims[2] * h + 0.5 * h});
  for (int k = 0; k < dims[2]; ++k) // row by row: the padding between rows stays void
    for (int j = 0; j < dims[1]; ++j) {
      const int64_t row = v.Index(0, j, k);
      std::fill(v.MutableFill() + row, v.MutableFill() + row + dims[0], Voxmap::kFull);
      if (material != 1.0f)
        for (int i = 0; i < dims[0]; ++i)
          v.SetMaterial(row + i, material);
    }
  v.RebuildOccupancy();
  return v;
}

} // namespace bm
