// bmBoneBlock.h - a rectangular block of bone as a voxmap (the drilling scene's workpiece).
#pragma once

#include <array>

#include "bmVoxmap.h"

namespace bm {

/// Block of sizeMm (x, y, z extents, mm) centred on x = y = 0 with its top face at z = 0, cut
/// into `resolution` voxels along its longest side (Docs/CostModel.md section 1); the voxel grid's
/// outer faces are the block's faces, so every voxel is full. material: scale (1 = cortical).
Voxmap MakeBoneBlock(const std::array<double, 3>& sizeMm, int resolution, float material = 1.0f);

} // namespace bm
