// bmSharedLibraryCheck.h - checks a shared library (a device driver such as OpenHaptics' libHD.so)
// before it is loaded and before any of its functions is called, so that a damaged or foreign file
// is refused with a message instead of bringing the process down: dlopen() maps the file's
// segments as its program headers describe them, and a segment that lies past the end of a
// truncated file raises SIGBUS when the loader touches it.
#pragma once

#include <string>

namespace bm {

/// The file dlopen(name) would load: `name` itself when it contains a '/', else the first
/// regular file of that name in $LD_LIBRARY_PATH's folders and then the system's library folders
/// (/usr/local/lib, /usr/lib/x86_64-linux-gnu, /usr/lib, /lib/x86_64-linux-gnu, /lib; the
/// machine's own multiarch folder on other machines). "" when none is found (dlopen may still find
/// it through the loader's cache).
std::string FindSharedLibrary(const std::string& name);

/// Throws std::runtime_error naming `path` and the problem unless it is a regular file holding an
/// ELF shared object for this machine (class, byte order, machine, type ET_DYN) whose program and
/// section header tables and every segment's file bytes lie inside the file (a truncated or
/// cut-short library is named as such). Reads the headers only (at most a few KiB).
void CheckSharedLibraryFile(const std::string& path);

/// The address of the function `name` in the dlopen()ed library `handle` (loaded from `path`, for
/// the messages). Throws std::runtime_error when the library does not export it, when the symbol
/// is not a function (a data object of that name would be called as code), or when it is defined
/// by another library than `handle` itself (a dependency's function of the same name).
void* BindLibraryFunction(void* handle, const char* name, const std::string& path);

} // namespace bm
