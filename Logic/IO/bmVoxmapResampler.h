// bmVoxmapResampler.h - from a bone segmentation at CT resolution to the voxmap.
//
// Grid: "resolution N" = the region of interest's bounding box divided into N cells along its
// longest axis (Docs/CostModel.md section 1): isotropic spacing h = longest extent / N, dims[a] =
// ceil(extent[a] / h), the grid anchored at the box's low corner (so it covers the box, exceeding
// it by less than one voxel on the high side of the shorter axes). The voxmap's origin is the world
// position (mm) of the centre of voxel (0, 0, 0); its axes are the world axes, so tools and CT
// agree in mm whatever the CT's own orientation.
//
// Fill: the voxel's bone fraction is the mean, over the voxel, of the CT bone fraction
// (bmBoneSegmenter: partial-volume fractions at the CT's resolution) interpolated trilinearly,
// estimated at m^3 points (m = ceil(1.5 h / smallest CT spacing), 1..8). The integral of a
// trilinear interpolant equals the sum of its samples times the voxel volume, so the voxmap holds
// the segmentation's bone volume at any resolution (within 3 %, Docs/Segmentation.md), thin
// cortex included. That field ramps over about one CT voxel on each side of the surface, and its
// faint outer part would stand in front of the bone as a haze of nearly empty voxels that a rigid
// part (a reamer's guide nipple in its pilot hole) meets as bone. So the bone voxels' fractions are
// then stretched, g(f) = clamp(0.5 + 3 (f - c), 0, 1) (void stays void), with c found by bisection
// so that the total volume is unchanged: the ramp becomes about a third as wide, and the volume
// stays the segmentation's. fill = round(g * Voxmap::kFull). The grid must cover the bone's voxels grown by half a CT voxel (the reach of
// the interpolant) for the volume to be kept whole.
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

/// Cells along longestMm (mm) whose voxel is no finer than spacingMm (mm): floor(longest /
/// spacing), at least 8; 0 (no limit) when spacingMm or longestMm is not a positive number.
int CellsNoFinerThan(double longestMm, double spacingMm);

/// Bytes a voxmap of `grid` needs (fill + material + brick occupancy).
uint64_t VoxmapBytes(const VoxmapGrid& grid);

/// Resample the segmentation into a voxmap on `grid` (see above). threads = 0: all cores.
/// Progress stage "resampling into the voxmap"; cancel -> Cancelled.
Voxmap ResampleToVoxmap(const BoneSegmentation& seg, const VoxmapGrid& grid,
                        const MaterialMapping& material = {}, const Progress& progress = {},
                        int threads = 0);

} // namespace bm
