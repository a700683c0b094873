// bmBoneSeparation.h - the bone you mean, split from the bones it touches across a joint space.
//
// In a CT the joint space between two bones (the glenoid and the humeral head, 3-5 mm apart) is
// blurred by the scanner's point spread and the voxel's partial volume, so the bone threshold
// often joins the two bones into one connected component. The separation cuts such necks with
// ITK's morphology, keeping the bone at the include seed and dropping those at exclude seeds:
//  1. distance map: itk::SignedMaurerDistanceMapImageFilter, depth of each bone voxel below the
//     mask's surface (mm, image spacing);
//  2. erosion: the voxels deeper than d (d = 1, 2, 3, ... smallest voxel spacings, up to
//     maxDepthMm) split into 6-connected components (itk::ConnectedComponentImageFilter); the
//     smallest d at which the include seed's core and every exclude seed's core lie in different
//     components is used (a seed's core: the nearest eroded voxel within d + 1 voxels);
//  3. regrowth: itk::MorphologicalWatershedFromMarkersImageFilter floods the negated distance map
//     from the eroded components, so every bone voxel returns to the core it is deepest towards
//     and the cut falls on the neck;
//  4. the region of the include seed is kept (without one: the largest region at no exclude
//     seed, once its core holds at least a tenth of the eroded bone); the others are dropped.
// A bone thinner than 2 d at its seed loses its core: the separation then fails with a message
// naming the seed and the depth.
#pragma once

#include "bmMask.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace bm {

struct SeparationOptions {
  /// Deepest erosion tried, mm (default 8 mm: necks up to 16 mm across are cut).
  double maxDepthMm = 8.0;
};

struct SeparationResult {
  double depthMm = 0; ///< erosion depth that split the seeds, mm (0: nothing to split)
  int regions = 0;    ///< regions the bone was split into
  int64_t keptVoxels = 0;
  int64_t droppedVoxels = 0;
};

/// Keep in `mask` (non-zero = bone, one or more touching bones) only the bone at voxel
/// `include` (nullopt: the largest region at no exclude voxel), dropping the bones at the
/// `exclude` voxels (indices into the mask's largest region, each on a non-zero voxel). Does
/// nothing when exclude is empty. Throws std::runtime_error when the seeds cannot be separated
/// within options.maxDepthMm. Progress stage "separating bones".
SeparationResult SeparateBones(MaskImage* mask, const std::optional<std::array<int, 3>>& include,
                               const std::vector<std::array<int, 3>>& exclude,
                               const SeparationOptions& options = {},
                               const Progress& progress = {});

} // namespace bm
