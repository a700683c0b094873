#include "bmMemoryBudget.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace bm {

namespace {

std::string MiB(uint64_t bytes) {
  std::ostringstream os;
  os << (bytes + (1u << 20) - 1) / (1u << 20) << " MiB";
  return os.str();
}

} // namespace

uint64_t CgroupMemoryLimit(const std::string& root, const std::string& selfCgroup) {
  // The process's group paths: "0::/path" (v2), "N:memory:/path" (v1).
  std::string v2 = "/", v1 = "/";
  {
    std::ifstream in(selfCgroup);
    std::string line;
    while (std::getline(in, line)) {
      const size_t a = line.find(':'), b = line.find(':', a == std::string::npos ? a : a + 1);
      if (a == std::string::npos || b == std::string::npos)
        continue;
      const std::string controllers = line.substr(a + 1, b - a - 1), path = line.substr(b + 1);
      if (line.compare(0, a, "0") == 0 && controllers.empty())
        v2 = path;
      else if (("," + controllers + ",").find(",memory,") != std::string::npos)
        v1 = path;
    }
  }
  uint64_t best = 0;
  const auto consider = [&](const fs::path& file) {
    std::ifstream in(file);
    std::string text;
    if (!(in >> text) || text == "max")
      return;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
    if (end == text.c_str() || *end != '\0' || v == 0 || v >= (1ull << 60)) // "unlimited"
      return;
    best = best == 0 ? v : std::min<uint64_t>(best, v);
  };
  const fs::path r(root);
  for (const fs::path& dir : {r, r / fs::path(v2).relative_path(), r / "unified",
                              r / "unified" / fs::path(v2).relative_path()})
    consider(dir / "memory.max");
  for (const fs::path& dir : {r / "memory", r / "memory" / fs::path(v1).relative_path()})
    consider(dir / "memory.limit_in_bytes");
  return best;
}

uint64_t DefaultMemoryLimit() {
  long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  uint64_t usable =
      pages <= 0 || page <= 0 ? (uint64_t(16) << 30) / 3 : uint64_t(double(pages) * double(page));
  const uint64_t group = CgroupMemoryLimit();
  if (group > 0)
    usable = std::min(usable, group);
  return uint64_t(double(usable) * 0.75);
}

void CheckMemoryBudget(uint64_t bytes, uint64_t limitBytes, const std::string& what) {
  uint64_t limit = limitBytes ? limitBytes : DefaultMemoryLimit();
  if (bytes > limit)
    throw std::runtime_error(what + " needs " + MiB(bytes) + " of memory, more than the " +
                             MiB(limit) +
                             " allowed (raise the memory limit or crop the volume first)");
}

} // namespace bm
