// bmDicomWriting.h - what the DICOM writers share: files written atomically (DCMTK writes a
// hidden temporary beside the target, bmAtomicFile.h TemporarySibling, renamed into place only
// when complete), DCMTK's conditions as exceptions, decimal strings, DCMTK's log kept quiet.
#pragma once

#include <functional>
#include <string>

#include <dcmtk/ofstd/ofcond.h>

namespace bm {

/// Calls save(temporary) (returning "" on success, else DCMTK's error text) and renames the
/// temporary to `path`. Throws std::runtime_error "<what>: ..." naming the path on failure; the
/// temporary is removed and `path` untouched.
void SaveDicomAtomically(const std::string& path, const std::string& what,
                         const std::function<std::string(const std::string&)>& save);

/// Throws std::runtime_error "<writer>: <what>: <DCMTK's text>" when `c` is bad.
void CheckDicom(const OFCondition& c, const std::string& writer, const std::string& what);

/// `v` as a DICOM decimal string (at most 6 significant digits: "%.6g").
std::string DicomDecimal(double v);

/// DCMTK's log quiet below errors (its warnings on the headers-only reads would flood the
/// output); DCMTK's errors reach the caller as exceptions. Idempotent.
void QuietDicomLog();

} // namespace bm
