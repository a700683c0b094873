// bmFuzzScratch.h - a file per fuzz process for targets whose reader takes a path: the input is
// written there (same name each run, removed at exit).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace bmfuzz {

/// A folder of its own for this process, removed at exit.
inline const std::filesystem::path& ScratchFolder() {
  struct Folder {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("bmfuzz-" + std::to_string(::getpid()));
    Folder() { std::filesystem::create_directories(path); }
    ~Folder() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static Folder folder;
  return folder.path;
}

/// Writes the input to `name` in the scratch folder and returns its path.
inline std::string WriteInput(const std::string& name, const uint8_t* data, size_t size) {
  const std::filesystem::path p = ScratchFolder() / name;
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return p.string();
}

} // namespace bmfuzz
