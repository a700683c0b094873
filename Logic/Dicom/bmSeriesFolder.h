// bmSeriesFolder.h - a PACS series kept in a folder of its own: where it goes under a parent
// folder (one folder per Series Instance UID, e.g. a per-user cache), whether a folder already
// holds the series whole, and fetching it there unless it does (bmPacsConnection.h). A folder
// that holds the whole series is reused rather than fetched again; one that holds anything else
// is refused, never overwritten.
#pragma once

#include <string>

#include "bmPacsClient.h" // PacsSeries

namespace bm {

class PacsConnection;

/// `parent`/<the Series Instance UID> (a UID from the network never reaches a path as it is:
/// anything but digits and dots becomes '_'). Throws std::invalid_argument when the UID is empty.
std::string SeriesFolder(const std::string& parent, const std::string& seriesInstanceUid);

/// The number of DICOM instances of series `seriesInstanceUid` in `folder`: -1 when the folder
/// does not exist, 0 when it is empty or holds anything else as well (a file that is not DICOM,
/// an instance of another series, a subfolder).
int HeldSeriesInstances(const std::string& folder, const std::string& seriesInstanceUid);

/// What FetchSeriesInto did.
struct SeriesFetch {
  int instances = 0;   ///< instances the folder holds now
  bool reused = false; ///< true when the folder already held the whole series (nothing fetched)
};

/// Fetches `series` (its study and series UIDs) into `folder` through `pacs`, unless the folder
/// already holds it whole: every file an instance of the series, as many as the PACS lists
/// (`series.instances`; when the PACS does not say, at least one), which is reused as it is.
/// Throws std::runtime_error naming the folder when it exists and holds anything else, or as
/// PacsConnection::GetSeries does (no folder left).
SeriesFetch FetchSeriesInto(const PacsConnection& pacs, const PacsSeries& series,
                            const std::string& folder);

} // namespace bm
