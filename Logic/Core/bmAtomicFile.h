// bmAtomicFile.h - saves that never leave a half-written file: write a temporary file beside the
// target, flush it, then rename it over the target (atomic on POSIX file systems).
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace bm {

/// Writes `content` to `path` atomically. Throws std::runtime_error naming the path on failure;
/// the target is then untouched.
void WriteFileAtomic(const std::string& path, const std::string& content);

/// Streams into a temporary file through `write`, then renames it to `path`. If `write` throws,
/// the temporary file is removed and the exception propagates.
void WriteFileAtomic(const std::string& path, const std::function<void(std::ostream&)>& write);

/// Writes several files so that either all of them appear or none: every file is written to a
/// temporary sibling first, then all are renamed. Throws std::runtime_error naming the path on
/// failure, removing the temporaries.
void WriteFilesAtomic(const std::vector<std::pair<std::string, std::string>>& files);

/// A unique hidden temporary path beside `path` (same directory, so rename is atomic), with the
/// same extension: "dir/.name.tmp-PID-N.ext". The first call for a folder in this process also
/// removes that folder's stale temporaries (RemoveStaleTemporaries).
std::string TemporarySibling(const std::string& path);

/// Whether `name` (a file name, no folder) is a temporary of TemporarySibling's pattern
/// (".name.tmp-PID-N[.ext]"); its PID is stored in `pid`.
bool IsTemporaryName(const std::string& name, long& pid);

/// Removes the temporaries (files or folders of TemporarySibling's pattern) in `folder` that a
/// killed run left: those whose process no longer runs, or whose PID now belongs to a process
/// started after the temporary was last written (the PID was reused). Temporaries of running
/// writers are kept. Returns how many were removed; a folder that cannot be listed removes none.
int RemoveStaleTemporaries(const std::string& folder);

} // namespace bm
