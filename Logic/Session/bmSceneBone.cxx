// bmSceneBone.cxx - see bmSceneBone.h.
#include "bmSceneBone.h"

#include <stdexcept>

#include "bmMachiningSetup.h"
#ifdef BM_WITH_IO
#include "bmCTVoxmap.h"
#endif

namespace bm {

bool CanImportSceneBones() {
#ifdef BM_WITH_IO
  return true;
#else
  return false;
#endif
}

Voxmap MakeSceneBone(const Scene& scene, const BoneProgress& progress, bool noFinerThanCT,
                     double toolVoxelMm) {
  if (scene.bone.type == "block")
    return MakeSceneBlock(scene);
#ifdef BM_WITH_IO
  return MakeCTVoxmap(scene.bone.ct, scene.baseDir, scene.voxmapResolution, progress, noFinerThanCT,
                      toolVoxelMm);
#else
  (void)progress;
  (void)noFinerThanCT;
  (void)toolVoxelMm;
  throw std::runtime_error("scene '" + scene.name +
                           "' needs CT import, which this build leaves out");
#endif
}

} // namespace bm
