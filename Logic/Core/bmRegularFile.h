// bmRegularFile.h - whether a path a user gave is a plain file to read: not a folder, FIFO,
// device or socket (a FIFO blocks the first read, /dev/zero never ends), and not a kernel
// interface file under /proc or /sys, which stat() calls regular but which may block
// (/proc/kmsg) or be endless. Links are followed: the target is what is checked.
#pragma once

#include <cstdint>
#include <exception>
#include <string>

namespace bm {

/// Why `path` is not a plain file to read ("a FIFO (named pipe)", "a kernel interface file
/// (/proc, /sys)", "missing or unreadable", ...), or "" when it is one.
std::string NotARegularFile(const std::string& path);

/// The whole content of the plain file `path`, at most maxBytes bytes. Throws std::runtime_error
/// "<role> '<path>' is <why>, not a regular file" (NotARegularFile) or "... is larger than N
/// bytes" before reading it.
std::string ReadRegularFile(const std::string& path, uint64_t maxBytes, const std::string& role);

/// An optional table a user may point anywhere (an environment variable, the resources): read
/// with ReadRegularFile and parsed by parse(text, path). A file that is missing gives an empty
/// T with "no <role> at <path>" in `error` (optional); one that is not a plain file, too large or
/// refused by `parse` gives an empty T with the reason.
template <class T, class Parse>
T LoadOptionalTable(const std::string& path, uint64_t maxBytes, const std::string& role,
                    Parse parse, std::string* error) {
  if (NotARegularFile(path) == "missing or unreadable") {
    if (error)
      *error = "no " + role + " at " + path;
    return T{};
  }
  try {
    return parse(ReadRegularFile(path, maxBytes, "the " + role), path);
  } catch (const std::exception& e) {
    if (error)
      *error = e.what();
    return T{};
  }
}

} // namespace bm
