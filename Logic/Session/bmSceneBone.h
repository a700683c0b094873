// bmSceneBone.h - a scene's bone as a voxmap: its block (Core), or its CT, phantom or saved voxmap
// through the IO library (bmCTVoxmap.h) when this build has it. One rule for bmsim, the BM Session
// source and the benchmarks (Docs/Session.md, "Building a session").
#pragma once

#include <functional>
#include <string>

#include "bmInputFiles.h"
#include "bmScene.h"
#include "bmVoxmap.h"

namespace bm {

/// Progress of a bone import: fraction done (0..1) and the stage; returning false cancels.
using BoneProgress = std::function<bool(double, const std::string&)>;

/// Whether this build can build CT, phantom and saved-voxmap bones (the IO library is linked).
bool CanImportSceneBones();

/// The scene's bone: MakeSceneBlock for a block; for bone.type "ct" the CT, phantom or voxmap file
/// it names (relative paths from scene.baseDir) at scene.voxmapResolution cells along the region's
/// longest side (a voxmap file keeps its own); with noFinerThanCT (default false) fewer where the
/// CT's finest spacing is coarser than that voxel, though voxels of at most toolVoxelMm (mm; 0:
/// no such limit) (a session's grid, bmSessionGrid.h). Throws std::runtime_error naming the
/// scene when the bone needs the IO library and this build has none, or naming the import's
/// problem.
Voxmap MakeSceneBone(const Scene& scene, const BoneProgress& progress = {},
                     bool noFinerThanCT = false, double toolVoxelMm = 0);

/// Adds to `inputs` the files the scene's bone is read from (a CT with its detached data file or
/// DICOM folder, a saved voxmap; relative paths from scene.baseDir), so that no output replaces
/// one. A block or a phantom reads none.
void AddSceneBoneInputs(const Scene& scene, InputFiles& inputs);

} // namespace bm
