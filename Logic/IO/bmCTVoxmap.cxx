#include "bmCTVoxmap.h"

#include <nlohmann/json.hpp>

#include "bmImport.h"

namespace bm {

Voxmap MakeCTVoxmap(const nlohmann::json& ct, const std::string& baseDir, int resolution,
                    const std::function<bool(double, const std::string&)>& progress) {
  nlohmann::json bone = ct;
  if (resolution > 0)
    bone["resolution"] = resolution;
  return VoxmapFromScene(bone, baseDir, progress ? Progress(progress) : Progress());
}

} // namespace bm
