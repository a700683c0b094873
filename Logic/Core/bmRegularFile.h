// bmRegularFile.h - whether a path a user gave is a plain file to read: not a folder, FIFO,
// device or socket (a FIFO blocks the first read, /dev/zero never ends), and not a kernel
// interface file under /proc or /sys, which stat() calls regular but which may block
// (/proc/kmsg) or be endless. Links are followed: the target is what is checked.
#pragma once

#include <cstdint>
#include <string>

namespace bm {

/// Why `path` is not a plain file to read ("a FIFO (named pipe)", "a kernel interface file
/// (/proc, /sys)", "missing or unreadable", ...), or "" when it is one.
std::string NotARegularFile(const std::string& path);

/// The whole content of the plain file `path`, at most maxBytes bytes. Throws std::runtime_error
/// "<role> '<path>' is <why>, not a regular file" (NotARegularFile) or "... is larger than N
/// bytes" before reading it.
std::string ReadRegularFile(const std::string& path, uint64_t maxBytes, const std::string& role);

} // namespace bm
