// bmVoxmapResampler.h - from a bone segmentation at CT resolution to the voxmap.
//
// Grid: "resolution N" = the region of interest's bounding box divided into N cells along its
// longest axis (Docs/CostModel.md section 1): isotropic spacing h = longest extent / N, dims[a] =
// ceil(extent[a] / h), the grid anchored at the box's low corner (so it covers the box, exceeding
// it by less than one voxel on the high side of the shorter axes). The voxmap's origin is the world
// position (mm) of the centre of voxel (0, 0, 0); its axes are the world axes, so tools and CT
// agree in mm whatever the CT's own orientation.
//
// Fill: each voxel is sampled at m^3 points (m = ceil(h / smallest CT spacing), at most 6; m = 1
// when the voxmap is finer than the CT). At each point the CT bone fraction is interpolated
// trilinearly and sharpened into a sub-voxel surface: the signed distance to the 0.5 iso-surface is
// estimated as d = (F - 0.5) / |grad F| (mm) and the point's share of bone is clamp(0.5 + d / h_s)
// with h_s = h / m the sample spacing. This keeps the CT's surface position (a symmetric ramp
// conserves volume on average), gives a sharp surface at any voxmap resolution, and gives partial
// voxels along it; bone structures thinner than about half a CT voxel are lost. fill =
// round(share * Voxmap::kFull).
//
// Material scale (multiplies the cutting coefficients k_c, k_f): linear in HU, which is roughly
// proportional to bone mineral density, scale = clamp(HU_bone / corticalHU, minScale, 1) with
// corticalHU = 1200 HU (dense cortical bone and above = 1) and minScale = 0.05 (marrow, fat).
// HU_bone is the segmentation's bone HU at the nearest CT voxel (surface voxels use the HU of the
// bone next to them, not their diluted value).
#pragma once

#include "bmBoneSegmenter.h"
#include "bmProgress.h"
#include "bmVoxmap.h"

#include <array>
#include <cstdint>

namespace bm {

struct MaterialMapping {
  float corticalHU = 1200.0f; ///< HU at and above which the scale is 1 (cortical bone)
  float minScale = 0.05f;     ///< lowest scale (bone voxels of very low HU)
};

/// Material scale for a bone HU value (see above). NaN -> 1.
float MaterialScaleFromHU(float hu, const MaterialMapping& m = {});

struct VoxmapGrid {
  std::array<int, 3> dims{0, 0, 0};
  double spacing = 0;             ///< mm
  std::array<double, 3> origin{}; ///< world mm of the centre of voxel (0, 0, 0)
  int64_t NumVoxels() const { return int64_t(dims[0]) * dims[1] * dims[2]; }
};

/// The grid of resolution N (cells along the longest axis, N >= 1) over a world box (mm).
/// Throws std::invalid_argument on an empty box or N < 1.
VoxmapGrid GridForBox(const Box3& boxMm, int resolution);

/// Bytes a voxmap of `grid` needs (fill + material + brick occupancy).
uint64_t VoxmapBytes(const VoxmapGrid& grid);

/// Resample the segmentation into a voxmap on `grid` (see above). threads = 0: all cores.
/// Progress stage "resampling into the voxmap"; cancel -> Cancelled.
Voxmap ResampleToVoxmap(const BoneSegmentation& seg, const VoxmapGrid& grid,
                        const MaterialMapping& material = {}, const Progress& progress = {},
                        int threads = 0);

} // namespace bm
