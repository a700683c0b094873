// bmScapulaVoxmap.h - the scapula phantom sampled straight into a voxmap (bone fraction per voxel
// from sub-samples, no CT, no noise), for fast planning tests. World mm; the grid is axis-aligned
// and covers the phantom's bone box plus a margin.
#pragma once

#include "bmScapulaPhantom.h"
#include "bmVoxmap.h"

namespace bm {

/// Voxmap of spacing `spacingMm` (mm, > 0) with each voxel's fill = the fraction of its
/// samples^3 sub-samples that are bone (only voxels whose corners differ are sub-sampled) and its
/// material scale = the bone's cancellous/cortical HU ratio where the centre is cancellous (1
/// where cortical). `marginMm` of void around the bone box. Throws std::invalid_argument on a
/// non-positive spacing or samples < 1.
Voxmap MakeScapulaVoxmap(const ScapulaPhantom& phantom, double spacingMm, int samples = 3,
                         double marginMm = 3.0);

} // namespace bm
