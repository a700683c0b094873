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

/// The joint space of `phantom`'s voxmap `v` filled with bone over a disc of radius `radiusMm`
/// around the glenoid's axis (from 1 mm behind the face to 6 mm in front of it, outside the
/// humeral head less 1 mm), as thick slices fuse a narrow joint: one bone, no joint to find.
void BridgeJointSpace(Voxmap& v, const ScapulaPhantom& phantom, double radiusMm);

} // namespace bm
