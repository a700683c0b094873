#include "bmResources.h"

#include <cstdlib>
#include <system_error>

#include <dlfcn.h>

namespace bm {
namespace {
// The file of the executable or shared object this function was linked into.
std::filesystem::path ThisBinary() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&ThisBinary), &info) == 0 || !info.dli_fname)
    return {};
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path(info.dli_fname) : p;
}
} // namespace

std::filesystem::path ResourceDir() {
  if (const char* env = std::getenv("BM_RESOURCE_DIR"); env && *env)
    return env;
  // An installed prefix: walk up from the binary (at most four levels: bin/, or
  // lib/paraview-plugins/BoneMachining/) looking for share/BoneMachining/Scenes.
  std::filesystem::path dir = ThisBinary().parent_path();
  for (int up = 0; up < 4 && !dir.empty(); ++up) {
    const std::filesystem::path candidate = dir / "share" / "BoneMachining";
    std::error_code ec;
    if (std::filesystem::is_directory(candidate / "Scenes", ec))
      return candidate;
    if (dir == dir.parent_path())
      break;
    dir = dir.parent_path();
  }
#ifdef BM_SOURCE_RESOURCE_DIR
  return BM_SOURCE_RESOURCE_DIR;
#else
  return "Resources";
#endif
}

std::filesystem::path ResourcePath(const std::filesystem::path& relative) {
  return ResourceDir() / relative;
}

} // namespace bm
