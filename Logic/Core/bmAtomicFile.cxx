#include "bmAtomicFile.h"

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace bm {

std::string TemporarySibling(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path p(path);
  // Keeps the extension, so writers that pick a format by extension (ITK) still recognise it.
  std::string name(1, '.'); // built by appends: GCC 12 warns falsely on "." + std::string
  name += p.stem().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  name += p.extension().string();
  return (p.parent_path() / name).string();
}

void WriteFileAtomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string tmp = TemporarySibling(path);
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out)
        throw std::runtime_error("cannot write '" + path +
                                 "' (cannot create a file in its directory)");
      write(out);
      out.flush();
      if (!out)
        throw std::runtime_error("writing '" + path + "' failed");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec)
      throw std::runtime_error("cannot save '" + path + "': " + ec.message());
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

void WriteFileAtomic(const std::string& path, const std::string& content) {
  WriteFileAtomic(
      path, [&](std::ostream& out) { out.write(content.data(), std::streamsize(content.size())); });
}

void WriteFilesAtomic(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::string> temps;
  try {
    for (const auto& [path, content] : files) {
      temps.push_back(TemporarySibling(path));
      std::ofstream out(temps.back(), std::ios::binary | std::ios::trunc);
      if (!out)
        throw std::runtime_error("cannot write '" + path +
                                 "' (cannot create a file in its directory)");
      out.write(content.data(), std::streamsize(content.size()));
      out.flush();
      if (!out)
        throw std::runtime_error("writing '" + path + "' failed");
    }
    for (size_t i = 0; i < files.size(); ++i) {
      std::error_code ec;
      std::filesystem::rename(temps[i], files[i].first, ec);
      if (ec)
        throw std::runtime_error("cannot save '" + files[i].first + "': " + ec.message());
    }
  } catch (...) {
    for (const auto& t : temps) {
      std::error_code ec;
      std::filesystem::remove(t, ec);
    }
    throw;
  }
}

} // namespace bm
