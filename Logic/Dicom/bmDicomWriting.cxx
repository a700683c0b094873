// bmDicomWriting.cxx - see bmDicomWriting.h.
#include "bmDicomWriting.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <dcmtk/oflog/oflog.h>

#include "bmAtomicFile.h"

namespace bm {

void SaveDicomAtomically(const std::string& path, const std::string& what,
                         const std::function<std::string(const std::string&)>& save) {
  namespace fs = std::filesystem;
  const std::string tmp = TemporarySibling(path);
  std::error_code ec;
  const std::string error = save(tmp);
  if (!error.empty()) {
    fs::remove(tmp, ec);
    throw std::runtime_error(what + ": cannot write " + path + ": " + error);
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error(what + ": cannot write " + path + ": " + ec.message());
  }
}

void CheckDicom(const OFCondition& c, const std::string& writer, const std::string& what) {
  if (c.bad())
    throw std::runtime_error(writer + ": " + what + ": " + c.text());
}

std::string DicomDecimal(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

void QuietDicomLog() {
  static const bool once = [] {
    OFLog::configure(OFLogger::ERROR_LOG_LEVEL);
    return true;
  }();
  (void)once;
}

} // namespace bm
