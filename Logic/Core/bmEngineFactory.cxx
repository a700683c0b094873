#include "bmEngineFactory.h"

#include <map>
#include <mutex>
#include <stdexcept>

#include "bmCpuEngine.h"
#include "bmZhengEngine.h"

namespace bm {

namespace {
std::mutex& RegistryMutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, EngineMaker>& Registry() {
  static std::map<std::string, EngineMaker> r{
      {"cpu", [](const EngineContext& c) -> std::unique_ptr<Engine> {
         if (c.model.GetMethod() == Method::Zheng)
           return std::make_unique<ZhengEngine>(c.bone, c.tool, c.shell, c.model, c.threads);
         return std::make_unique<CpuEngine>(c.bone, c.tool, c.shell, c.model, c.threads);
       }}};
  return r;
}
} // namespace

void RegisterBackend(const std::string& name, EngineMaker maker) {
  std::lock_guard<std::mutex> lock(RegistryMutex());
  Registry()[name] = std::move(maker);
}

std::vector<std::string> Backends() {
  std::lock_guard<std::mutex> lock(RegistryMutex());
  std::vector<std::string> names{"cpu"};
  for (const auto& [name, maker] : Registry())
    if (name != "cpu")
      names.push_back(name);
  return names;
}

std::unique_ptr<Engine> MakeEngine(const std::string& backend, const EngineContext& ctx) {
  EngineMaker maker;
  {
    std::lock_guard<std::mutex> lock(RegistryMutex());
    auto it = Registry().find(backend);
    if (it == Registry().end()) {
      std::string names;
      for (const auto& [name, m] : Registry())
        names += (names.empty() ? "" : ", ") + name;
      throw std::invalid_argument("unknown backend '" + backend + "' (available: " + names + ")");
    }
    maker = it->second;
  }
  return maker(ctx);
}

} // namespace bm
