#include "bmAtomicFile.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace bm {

bool IsTemporaryName(const std::string& name, long& pid) {
  const size_t tag = name.rfind(".tmp-");
  if (name.size() < 2 || name[0] != '.' || tag == std::string::npos || tag == 0)
    return false;
  // PID '-' N, then the end or the extension.
  size_t i = tag + 5, digits = 0;
  long value = 0;
  for (; i < name.size() && std::isdigit(static_cast<unsigned char>(name[i])) && digits < 10;
       ++i, ++digits)
    value = value * 10 + (name[i] - '0');
  if (digits == 0 || i >= name.size() || name[i] != '-')
    return false;
  size_t counterDigits = 0;
  for (++i; i < name.size() && std::isdigit(static_cast<unsigned char>(name[i])); ++i)
    ++counterDigits;
  if (counterDigits == 0 || (i < name.size() && name[i] != '.'))
    return false;
  pid = value;
  return true;
}

namespace {
// When process `pid` started (s since the epoch, from /proc/<pid>/stat's start time in clock ticks
// after boot and /proc/stat's boot time); 0 when unknown.
double ProcessStartTime(long pid) {
  std::ifstream statFile("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(statFile, text))
    return 0;
  const size_t close = text.rfind(')'); // the command name may hold spaces and parentheses
  if (close == std::string::npos)
    return 0;
  std::istringstream fields(text.substr(close + 1));
  std::string field;
  for (int i = 3; i <= 22 && fields >> field; ++i)
    if (i == 22) {
      const double ticks = std::strtod(field.c_str(), nullptr);
      std::ifstream boot("/proc/stat");
      for (std::string line; std::getline(boot, line);)
        if (line.rfind("btime ", 0) == 0)
          return std::strtod(line.c_str() + 6, nullptr) + ticks / double(::sysconf(_SC_CLK_TCK));
    }
  return 0;
}
} // namespace

int RemoveStaleTemporaries(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::directory_iterator it(folder.empty() ? "." : folder, ec);
  if (ec)
    return 0;
  int removed = 0;
  for (const fs::directory_entry& entry : it) {
    long pid = 0;
    if (!IsTemporaryName(entry.path().filename().string(), pid) || pid <= 0 || pid == ::getpid())
      continue;
    bool stale = ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
    if (!stale) {
      // A running process with that PID: stale when it started after the file was last written.
      struct stat st {};
      const double started = ProcessStartTime(pid);
      stale = started > 0 && ::lstat(entry.path().c_str(), &st) == 0 &&
              double(st.st_mtime) + 1.0 < started;
    }
    if (stale && fs::remove_all(entry.path(), ec) > 0 && !ec)
      ++removed;
  }
  return removed;
}

std::string TemporarySibling(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path p(path);
  {
    // Once per folder and process: what killed runs left there goes first.
    static std::mutex m;
    static std::set<std::string> cleaned;
    std::error_code ec;
    const std::string folder =
        std::filesystem::absolute(p.parent_path().empty() ? "." : p.parent_path(), ec).string();
    std::lock_guard<std::mutex> lock(m);
    if (!ec && cleaned.insert(folder).second)
      RemoveStaleTemporaries(folder);
  }
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
