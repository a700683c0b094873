// bmFetchedSeries.h - a series being fetched from a PACS into a new folder (DIMSE C-GET,
// bmPacsClient.h; DICOMweb WADO-RS, bmDicomWebClient.h): the instances go into a hidden sibling of
// the folder (bmAtomicFile.h TemporarySibling), each named by its SOP Instance UID, and the folder
// appears only when every instance arrived (Commit); a fetch that fails leaves nothing.
#pragma once

#include <filesystem>
#include <string>

namespace bm {

class FetchedSeries {
public:
  /// Throws std::runtime_error when `folder` exists (a fetched series goes into a new folder).
  explicit FetchedSeries(const std::string& folder);
  /// Removes what was fetched unless committed.
  ~FetchedSeries();
  FetchedSeries(const FetchedSeries&) = delete;
  FetchedSeries& operator=(const FetchedSeries&) = delete;

  /// Where an instance with this SOP Instance UID is written: the hidden folder / UID.dcm (a UID
  /// from the network never reaches a path as it is: anything but digits and dots becomes '_').
  std::filesystem::path InstancePath(const std::string& sopInstanceUid) const;
  /// Checks that `got` instances (> 0) are the `expected` the server lists (< 0: it did not say)
  /// and renames the hidden folder onto the target. Returns `got`. Throws std::runtime_error
  /// "<server> sent ..." otherwise (the destructor then removes what was fetched).
  int Commit(const std::string& server, const std::string& seriesInstanceUid, int got,
             int expected);

private:
  std::filesystem::path Target, Staging;
  bool Committed = false;
};

} // namespace bm
