#include "bmScene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "bmJson.h"
#include "bmResources.h"

namespace bm {

namespace {
using json = nlohmann::json;

void CheckKeys(const json& j, const std::set<std::string>& allowed, const std::string& where) {
  if (!j.is_object())
    throw std::invalid_argument(where + " must be a JSON object");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!allowed.count(it.key()))
      throw std::invalid_argument("unknown field '" + it.key() + "' in " + where);
}

template <class T> T Get(const json& j, const char* key, const T& def, const std::string& where) {
  if (!j.contains(key) || j.at(key).is_null())
    return def;
  if constexpr (std::is_integral_v<T>) {
    // A number outside the integer's range (or not whole) would convert to another value, or
    // (NaN, 1e300) be undefined: refuse it by name.
    const json& v = j.at(key);
    if (v.is_number()) {
      const double x = v.get<double>();
      if (!(x >= double(std::numeric_limits<T>::min()) &&
            x <= double(std::numeric_limits<T>::max())) ||
          x != std::floor(x))
        throw std::invalid_argument("field '" + std::string(key) + "' in " + where +
                                    " must be a whole number within the integers, got " + v.dump());
    }
  }
  try {
    return j.at(key).get<T>();
  } catch (const std::exception&) {
    throw std::invalid_argument("field '" + std::string(key) + "' in " + where +
                                " has the wrong type");
  }
}

// A name that becomes a folder ("out/<name>"): it must stay one folder level inside it.
void CheckName(const std::string& name, const std::string& what, size_t maxLength) {
  if (name.empty() || name.size() > maxLength)
    throw std::invalid_argument(what + " must have 1 to " + std::to_string(maxLength) +
                                " characters, got " + std::to_string(name.size()));
  if (name.front() == '.')
    throw std::invalid_argument(what + " must not start with '.' (got '" + name +
                                "'): it names an output folder");
  for (char c : name)
    if (c == '/' || c == '\\' || static_cast<unsigned char>(c) < 32 || c == 127)
      throw std::invalid_argument(what +
                                  " must not contain '/', '\\' or control characters (got '" +
                                  name + "'): it names an output folder");
}

Eigen::Vector3d GetVec(const json& j, const char* key, const Eigen::Vector3d& def,
                       const std::string& where) {
  auto v = Get<std::vector<double>>(j, key, {def(0), def(1), def(2)}, where);
  if (v.size() != 3)
    throw std::invalid_argument("field '" + std::string(key) + "' in " + where +
                                " needs 3 numbers");
  return {v[0], v[1], v[2]};
}
} // namespace

Scene Scene::FromJson(const json& j) {
  CheckKeys(j,
            {"name", "tool", "bone", "trial", "voxmap_resolution", "shell_resolution", "method",
             "lips", "threads", "backend", "force_model", "description", "steps", "planning"},
            "scene");
  Scene s;
  s.name = Get<std::string>(j, "name", s.name, "scene");
  CheckName(s.name, "field 'name' in scene", 128);
  if (j.contains("tool"))
    s.tool = j.at("tool");
  MakeTool(s.tool); // validates the tool now
  if (j.contains("bone")) {
    const json& b = j.at("bone");
    CheckKeys(b, {"type", "size_mm", "material", "ct"}, "bone");
    s.bone.type = Get<std::string>(b, "type", s.bone.type, "bone");
    auto size = Get<std::vector<double>>(
        b, "size_mm", {s.bone.sizeMm[0], s.bone.sizeMm[1], s.bone.sizeMm[2]}, "bone");
    if (size.size() != 3)
      throw std::invalid_argument("field 'size_mm' in bone needs 3 numbers");
    s.bone.sizeMm = {size[0], size[1], size[2]};
    s.bone.material = Get<double>(b, "material", s.bone.material, "bone");
    if (b.contains("ct"))
      s.bone.ct = b.at("ct");
  }
  if (j.contains("trial")) {
    const json& t = j.at("trial");
    CheckKeys(t,
              {"feed_mm_per_rev", "speed_rpm", "entry_mm", "axis", "clearance_mm", "depth_mm",
               "extra_depth_mm", "frame_s"},
              "trial");
    s.trial.feedMmPerRev = Get<double>(t, "feed_mm_per_rev", s.trial.feedMmPerRev, "trial");
    s.trial.speedRpm = Get<double>(t, "speed_rpm", s.trial.speedRpm, "trial");
    s.trial.entry = GetVec(t, "entry_mm", s.trial.entry, "trial");
    s.trial.axis = GetVec(t, "axis", s.trial.axis, "trial");
    s.trial.clearanceMm = Get<double>(t, "clearance_mm", s.trial.clearanceMm, "trial");
    s.trial.depthMm = Get<double>(t, "depth_mm", s.trial.depthMm, "trial");
    s.trial.extraDepthMm = Get<double>(t, "extra_depth_mm", s.trial.extraDepthMm, "trial");
    s.trial.frameS = Get<double>(t, "frame_s", s.trial.frameS, "trial");
  }
  s.voxmapResolution = Get<int>(j, "voxmap_resolution", s.voxmapResolution, "scene");
  s.shellResolution = Get<int>(j, "shell_resolution", s.shellResolution, "scene");
  s.method = MethodFromString(Get<std::string>(j, "method", ToString(s.method), "scene"));
  const std::string lips = Get<std::string>(j, "lips", "averaged", "scene");
  if (lips == "averaged")
    s.lips = LipMode::TimeAveraged;
  else if (lips == "instantaneous")
    s.lips = LipMode::Instantaneous;
  else
    throw std::invalid_argument("field 'lips' must be 'averaged' or 'instantaneous', got '" + lips +
                                "'");
  s.threads = Get<int>(j, "threads", s.threads, "scene");
  s.backend = Get<std::string>(j, "backend", s.backend, "scene");
  if (j.contains("force_model"))
    s.forceModel = j.at("force_model");
  if (j.contains("planning")) {
    if (!j.at("planning").is_object())
      throw std::invalid_argument("field 'planning' in scene must be a JSON object");
    s.planning = j.at("planning");
  }
  if (j.contains("steps")) {
    const json& steps = j.at("steps");
    if (!steps.is_array() || steps.empty() || steps.size() > 16)
      throw std::invalid_argument("field 'steps' in scene must be a list of 1 to 16 steps");
    for (size_t i = 0; i < steps.size(); ++i) {
      const std::string where = "step " + std::to_string(i + 1);
      const json& st = steps[i];
      CheckKeys(st, {"name", "description", "tool", "trial", "shell_resolution"}, where);
      SceneStep step;
      step.name = Get<std::string>(st, "name", "step " + std::to_string(i + 1), where);
      CheckName(step.name, "field 'name' in " + where, 64);
      step.description = Get<std::string>(st, "description", "", where);
      step.tool = st.contains("tool") ? st.at("tool") : s.tool;
      step.trial = st.contains("trial") ? st.at("trial") : json::object();
      step.shellResolution = Get<int>(st, "shell_resolution", 0, where);
      s.steps.push_back(std::move(step));
    }
    for (size_t i = 0; i < s.steps.size(); ++i) {
      try {
        (void)s.Step(i); // validates the step's tool, trial and resolution now
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("step " + std::to_string(i + 1) + " ('" + s.steps[i].name +
                                    "'): " + e.what());
      }
    }
  }
  s.Validate();
  return s;
}

Scene Scene::Step(size_t i) const {
  if (i >= steps.size())
    throw std::out_of_range("scene '" + name + "' has no step " + std::to_string(i + 1));
  const SceneStep& step = steps[i];
  json j = ToJson();
  j.erase("steps");
  j.erase("planning");
  j["tool"] = step.tool;
  if (!step.trial.is_object())
    throw std::invalid_argument("field 'trial' must be a JSON object");
  for (auto it = step.trial.begin(); it != step.trial.end(); ++it)
    j["trial"][it.key()] = it.value();
  if (step.shellResolution > 0)
    j["shell_resolution"] = step.shellResolution;
  Scene s = FromJson(j);
  s.name = name + ": " + step.name; // both checked; the step's folder is named by its number
  s.baseDir = baseDir;
  return s;
}

Scene Scene::WithVoxmapResolution(int cells) const {
  if (cells < 8 || cells > 4096)
    throw std::invalid_argument("voxmap resolution must be in [8, 4096], got " +
                                std::to_string(cells));
  Scene s = *this;
  s.voxmapResolution = cells;
  s.shellResolution = std::clamp(
      int(std::lround(double(shellResolution) * cells / double(voxmapResolution))), 8, 4096);
  return s;
}

void Scene::Validate() const {
  auto range = [](double v, double lo, double hi, const std::string& what) {
    if (!(v >= lo && v <= hi))
      throw std::invalid_argument(what + " must be in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "], got " + std::to_string(v));
  };
  range(voxmapResolution, 8, 4096, "field 'voxmap_resolution' (voxmap resolution)");
  range(shellResolution, 8, 4096, "field 'shell_resolution' (shell resolution)");
  range(threads, 1, 64, "field 'threads'");
  range(trial.feedMmPerRev, 1e-5, 1.0, "field 'feed_mm_per_rev' in trial (feed)");
  range(trial.speedRpm, 1.0, 100000.0, "field 'speed_rpm' in trial (spindle speed)");
  range(trial.frameS, 1e-5, 0.1, "field 'frame_s' in trial (frame period)");
  range(trial.clearanceMm, 0.0, 100.0, "field 'clearance_mm' in trial");
  range(trial.extraDepthMm, 0.0, 100.0, "field 'extra_depth_mm' in trial");
  if (trial.depthMm >= 0)
    range(trial.depthMm, 0.0, 200.0, "field 'depth_mm' in trial");
  if (!(trial.axis.norm() > 0.5 && trial.axis.norm() < 2.0) || !trial.axis.allFinite())
    throw std::invalid_argument("field 'axis' in trial must be a unit vector");
  if (!trial.entry.allFinite())
    throw std::invalid_argument("field 'entry_mm' in trial must be finite");
  for (int a = 0; a < 3; ++a)
    range(trial.entry(a), -10000.0, 10000.0, "field 'entry_mm' in trial (mm)");
  if (bone.type == "block") {
    for (double v : bone.sizeMm)
      range(v, 1e-3, 1000.0, "field 'size_mm' in bone (block size)");
    range(bone.material, 0.0, 10.0, "field 'material' in bone (material scale)");
  } else if (bone.type == "ct") {
    if (!bone.ct.is_object() ||
        !(bone.ct.contains("ct") || bone.ct.contains("phantom") || bone.ct.contains("voxmap")))
      throw std::invalid_argument(
          "bone of type 'ct' needs a 'ct' object naming a \"ct\", \"phantom\" or \"voxmap\"");
  } else {
    throw std::invalid_argument("bone type must be 'block' or 'ct', got '" + bone.type + "'");
  }
  if (backend != "cpu" && backend != "opencl")
    throw std::invalid_argument("backend must be 'cpu' or 'opencl', got '" + backend + "'");
}

std::vector<std::string> Scene::BuiltinNames() {
  std::vector<std::string> names{"drilling"};
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(ResourcePath("Scenes"), ec))
    if (e.path().extension() == ".json" && e.path().stem() != "drilling")
      names.push_back(e.path().stem().string());
  std::sort(names.begin() + 1, names.end());
  return names;
}

Scene Scene::Builtin(const std::string& name) {
  if (name == "drilling")
    return Scene{};
  const std::filesystem::path file = ResourcePath("Scenes") / (name + ".json");
  if (name.find('/') == std::string::npos && std::filesystem::exists(file)) {
    Scene s = Load(file.string());
    return s;
  }
  std::string list;
  for (const auto& n : BuiltinNames())
    list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("no built-in scene '" + name + "' (built-in: " + list + ")");
}

Scene Scene::Load(const std::string& path) {
  if (std::filesystem::is_directory(path))
    throw std::runtime_error("scene file '" + path + "' is a folder");
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error("scene file '" + path +
                             "' is not a regular file (a FIFO would block the read)");
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read scene file '" + path + "'");
  const json j = ParseJson(in, "scene file '" + path + "'");
  Scene s = FromJson(j);
  s.baseDir = std::filesystem::absolute(path).parent_path().string();
  return s;
}

json Scene::ToJson() const {
  json j;
  j["name"] = name;
  j["tool"] = tool;
  j["bone"] = {{"type", bone.type}};
  if (bone.type == "block") {
    j["bone"]["size_mm"] = bone.sizeMm;
    j["bone"]["material"] = bone.material;
  } else {
    j["bone"]["ct"] = bone.ct;
  }
  j["trial"] = {{"feed_mm_per_rev", trial.feedMmPerRev},
                {"speed_rpm", trial.speedRpm},
                {"entry_mm", {trial.entry(0), trial.entry(1), trial.entry(2)}},
                {"axis", {trial.axis(0), trial.axis(1), trial.axis(2)}},
                {"clearance_mm", trial.clearanceMm},
                {"extra_depth_mm", trial.extraDepthMm},
                {"frame_s", trial.frameS}};
  if (trial.depthMm >= 0)
    j["trial"]["depth_mm"] = trial.depthMm;
  j["voxmap_resolution"] = voxmapResolution;
  j["shell_resolution"] = shellResolution;
  j["method"] = ToString(method);
  j["lips"] = lips == LipMode::TimeAveraged ? "averaged" : "instantaneous";
  j["threads"] = threads;
  j["backend"] = backend;
  if (!forceModel.is_null())
    j["force_model"] = forceModel;
  if (!steps.empty()) {
    j["steps"] = json::array();
    for (const SceneStep& st : steps) {
      json o = {{"name", st.name}, {"tool", st.tool}, {"trial", st.trial}};
      if (!st.description.empty())
        o["description"] = st.description;
      if (st.shellResolution > 0)
        o["shell_resolution"] = st.shellResolution;
      j["steps"].push_back(std::move(o));
    }
  }
  if (!planning.is_null())
    j["planning"] = planning;
  return j;
}

} // namespace bm
