// bmSceneOverrides.cxx - see bmSceneOverrides.h.
#include "bmSceneOverrides.h"
#include "bmCheckRange.h"
#include "bmJson.h"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace bm {

namespace {

nlohmann::json ParseObject(const std::string& text, const char* what) {
  nlohmann::json j;
  try {
    j = ParseJson(text, what); // at most kMaxJsonDepth levels (bmJson.h)
  } catch (const std::exception& e) {
    throw std::invalid_argument(std::string(what) + " is not JSON: " + e.what());
  }
  if (!j.is_object())
    throw std::invalid_argument(std::string(what) + " must be a JSON object");
  return j;
}

} // namespace

Scene ResolveScene(const std::string& nameOrFile) {
  if (nameOrFile.empty())
    throw std::invalid_argument("no scene named: give a built-in scene name or a scene file");
  std::error_code ec;
  if (std::filesystem::path(nameOrFile).extension() == ".json" ||
      std::filesystem::exists(nameOrFile, ec))
    return Scene::Load(nameOrFile);
  return Scene::Builtin(nameOrFile);
}

Scene ApplyOverrides(const Scene& scene, const SceneOverrides& o) {
  if (o.voxmapResolution != 0)
    CheckRange("the voxmap resolution (cells)", o.voxmapResolution, 8, 4096);
  if (o.shellResolution != 0)
    CheckRange("the shell resolution (cells)", o.shellResolution, 8, 4096);
  nlohmann::json j = scene.ToJson();
  if (o.shellResolution > 0)
    j["shell_resolution"] = o.shellResolution;
  if (o.voxmapResolution > 0 && o.shellResolution > 0)
    j["voxmap_resolution"] = o.voxmapResolution;
  if (!o.toolJson.empty())
    j["tool"] = ParseObject(o.toolJson, "the tool specification");
  if (!o.method.empty()) {
    if (o.method != "lazar" && o.method != "zheng")
      throw std::invalid_argument("the method must be lazar or zheng, not '" + o.method + "'");
    // The scene's force-model coefficients belong to its method: kept for the same method,
    // dropped for the other one (its defaults apply).
    if (j.value("method", std::string()) != o.method)
      j.erase("force_model");
    j["method"] = o.method;
  }
  if (!o.boneFile.empty() && !o.boneCTJson.empty())
    throw std::invalid_argument("set either a bone file or a CT bone, not both");
  if (!o.boneFile.empty()) {
    const std::filesystem::path file = std::filesystem::absolute(o.boneFile);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
      throw std::runtime_error("the bone file '" + file.string() + "' does not exist");
    j["bone"] = {{"type", "ct"}, {"ct", {{"voxmap", file.string()}}}};
  }
  if (!o.boneCTJson.empty()) {
    const nlohmann::json ct = ParseObject(o.boneCTJson, "the CT bone description");
    if (!ct.contains("ct"))
      throw std::invalid_argument("the CT bone description must be a JSON object with \"ct\"");
    j["bone"] = {{"type", "ct"}, {"ct", ct}};
  }
  if (o.entryMm.has_value() != o.axis.has_value())
    throw std::invalid_argument("the trial override needs both an entry point and an axis");
  if (o.entryMm) {
    const Eigen::Vector3d& e = *o.entryMm;
    const Eigen::Vector3d& a = *o.axis;
    if (!e.allFinite())
      throw std::invalid_argument("the trial entry point must be finite (world mm)");
    if (!a.allFinite() || !(a.norm() > 0))
      throw std::invalid_argument("the trial axis must be finite and non-zero");
    const Eigen::Vector3d unit = a.normalized();
    j["trial"]["entry_mm"] = {e[0], e[1], e[2]};
    j["trial"]["axis"] = {unit[0], unit[1], unit[2]};
  }
  if (o.feedMmPerRev) {
    CheckRange("the feed (mm/rev)", *o.feedMmPerRev, 1e-5, 1.0);
    j["trial"]["feed_mm_per_rev"] = *o.feedMmPerRev;
  }
  if (o.speedRpm) {
    CheckRange("the spindle speed (rpm)", *o.speedRpm, 1.0, 1e5);
    j["trial"]["speed_rpm"] = *o.speedRpm;
  }
  if (o.threads) {
    CheckRange("the thread count", *o.threads, 1, 64);
    j["threads"] = *o.threads;
  }
  if (!o.backend.empty())
    j["backend"] = o.backend;
  if (!o.lips.empty())
    j["lips"] = o.lips;
  Scene out = Scene::FromJson(j);
  out.baseDir = scene.baseDir;
  if (o.voxmapResolution > 0 && o.shellResolution == 0)
    out = out.WithVoxmapResolution(o.voxmapResolution);
  return out;
}

} // namespace bm
