#include "bmFetchedSeries.h"

#include "bmAtomicFile.h"

#include <cctype>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace bm {

FetchedSeries::FetchedSeries(const std::string& folder) : Target(fs::absolute(folder)) {
  if (fs::exists(Target))
    throw std::runtime_error("'" + Target.string() +
                             "' exists: a fetched series goes into a new folder");
  fs::create_directories(Target.parent_path());
  Staging = TemporarySibling(Target.string()); // hidden; a stale one is removed later
  fs::create_directories(Staging);
}

FetchedSeries::~FetchedSeries() {
  std::error_code ec;
  if (!Committed)
    fs::remove_all(Staging, ec);
}

fs::path FetchedSeries::InstancePath(const std::string& sopInstanceUid) const {
  std::string name = sopInstanceUid;
  for (char& ch : name)
    if (!std::isdigit(static_cast<unsigned char>(ch)) && ch != '.')
      ch = '_';
  return Staging / (name + ".dcm");
}

int FetchedSeries::Commit(const std::string& server, const std::string& seriesInstanceUid, int got,
                          int expected) {
  if (got == 0)
    throw std::runtime_error(server + " sent no instance of series " + seriesInstanceUid);
  if (expected >= 0 && got != expected)
    throw std::runtime_error(server + " sent " + std::to_string(got) + " instance(s) of series " +
                             seriesInstanceUid + ", of the " + std::to_string(expected) +
                             " it lists");
  fs::rename(Staging, Target);
  Committed = true;
  return got;
}

} // namespace bm
