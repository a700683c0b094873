// bmDicomFileSave.h - DICOM files written atomically: DCMTK writes a hidden temporary beside the
// target (bmAtomicFile.h TemporarySibling), which is renamed into place only when complete.
#pragma once

#include <functional>
#include <string>

namespace bm {

/// Calls save(temporary) (returning "" on success, else DCMTK's error text) and renames the
/// temporary to `path`. Throws std::runtime_error "<what>: ..." naming the path on failure; the
/// temporary is removed and `path` untouched.
void SaveDicomAtomically(const std::string& path, const std::string& what,
                         const std::function<std::string(const std::string&)>& save);

/// DCMTK's log quiet below errors (its warnings on the headers-only reads would flood the
/// output); DCMTK's errors reach the caller as exceptions. Idempotent.
void QuietDicomLog();

} // namespace bm
