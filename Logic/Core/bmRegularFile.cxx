#include "bmRegularFile.h"

#include <sys/stat.h>
#include <sys/vfs.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace bm {

namespace {

// Kernel file systems whose "regular" files are interfaces, not data (linux/magic.h).
constexpr long kProcMagic = 0x9fa0, kSysfsMagic = 0x62656572, kDebugfsMagic = 0x64626720,
               kTracefsMagic = 0x74726163, kSecurityfsMagic = 0x73636673;

} // namespace

std::string NotARegularFile(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return "missing or unreadable";
  if (S_ISDIR(st.st_mode))
    return "a folder";
  if (S_ISFIFO(st.st_mode))
    return "a FIFO (named pipe)";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode))
    return "a device";
  if (S_ISSOCK(st.st_mode))
    return "a socket";
  if (!S_ISREG(st.st_mode))
    return "not a regular file";
  struct statfs fs {};
  if (::statfs(path.c_str(), &fs) == 0) {
    const long type = long(fs.f_type);
    if (type == kProcMagic || type == kSysfsMagic || type == kDebugfsMagic ||
        type == kTracefsMagic || type == kSecurityfsMagic)
      return "a kernel interface file (/proc, /sys)";
  }
  return "";
}

std::string ReadRegularFile(const std::string& path, uint64_t maxBytes, const std::string& role) {
  const std::string why = NotARegularFile(path);
  if (!why.empty())
    throw std::runtime_error(role + " '" + path + "' is " + why + ", not a regular file");
  struct stat st {};
  ::stat(path.c_str(), &st);
  if (uint64_t(st.st_size) > maxBytes)
    throw std::runtime_error(role + " '" + path + "' is larger than " + std::to_string(maxBytes) +
                             " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error("cannot read " + role + " '" + path + "'");
  std::string text;
  text.resize(size_t(st.st_size));
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(size_t(in.gcount()));
  return text;
}

} // namespace bm
