// bmDicomFileSave.cxx - see bmDicomFileSave.h.
#include "bmDicomFileSave.h"

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

void QuietDicomLog() {
  static const bool once = [] {
    OFLog::configure(OFLogger::ERROR_LOG_LEVEL);
    return true;
  }();
  (void)once;
}

} // namespace bm
