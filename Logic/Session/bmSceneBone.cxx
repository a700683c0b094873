// bmSceneBone.cxx - see bmSceneBone.h.
#include "bmSceneBone.h"

#include <stdexcept>

#include "bmMachiningSetup.h"
#ifdef BM_WITH_IO
#include "bmCTVoxmap.h"
#include "bmHeaderCheck.h"
#endif

#include <filesystem>

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

void AddSceneBoneInputs(const Scene& scene, InputFiles& inputs) {
  if (scene.bone.type != "ct" || !scene.bone.ct.is_object())
    return;
  for (const char* key : {"ct", "voxmap"}) {
    if (!scene.bone.ct.contains(key) || !scene.bone.ct[key].is_string())
      continue;
    const std::filesystem::path p(scene.bone.ct[key].get<std::string>());
    const std::string path =
        (p.is_absolute() || scene.baseDir.empty() ? p : std::filesystem::path(scene.baseDir) / p)
            .string();
#ifdef BM_WITH_IO
    AddCTInputs(inputs, path, std::string("the scene's ") + (key[0] == 'c' ? "CT" : "voxmap"));
#else
    inputs.AddFile(path, "the scene's bone");
#endif
  }
}

} // namespace bm
