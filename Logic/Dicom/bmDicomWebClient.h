// bmDicomWebClient.h - a PACS over DICOMweb (HTTP, libcurl): find series (QIDO-RS), fetch one
// into a folder (WADO-RS, multipart/related), store files (STOW-RS), the same three operations
// and guarantees as bmPacsClient.h's DIMSE ones (Docs/Dicom.md "PACS"): errors name the server,
// the request and the reason (the HTTP status, curl's message); a fetched series is written under
// a temporary sibling and renamed onto the target only when whole.
//
// Units: s (timeouts).
#pragma once

#include <string>
#include <vector>

#include "bmPacsClient.h" // PacsQuery, PacsSeries

namespace bm {

/// A DICOMweb service: its root URL, e.g. http://127.0.0.1:8042/dicom-web (Orthanc's plugin).
struct DicomWebServer {
  std::string url;   ///< http:// or https://, without a trailing slash
  int timeoutS = 30; ///< connection and whole-request timeout, s, in [1, 3600]
};

/// Whether `text` names a DICOMweb root (http:// or https://) rather than a DIMSE AET@host:port.
bool IsDicomWebUrl(const std::string& text);

/// QIDO-RS (GET {url}/series?...): the series matching `q`. Throws std::runtime_error when the
/// server cannot be reached, answers another status than 200/204, or not a JSON array.
std::vector<PacsSeries> FindSeriesWeb(const DicomWebServer& server, const PacsQuery& q);

/// WADO-RS (GET {url}/studies/{study}/series/{series}, multipart/related of application/dicom)
/// into `folder` (created; it must not exist yet), one file per instance named by its SOP Instance
/// UID. The study, when empty, is found first (QIDO-RS). Returns the instances written. Throws
/// std::runtime_error, leaving no folder, when the series is unknown, a part is not DICOM, or
/// fewer instances arrive than the server lists.
int GetSeriesWeb(const DicomWebServer& server, const std::string& studyInstanceUid,
                 const std::string& seriesInstanceUid, const std::string& folder);

/// STOW-RS (POST {url}/studies, multipart/related): the files, all in one request. Throws
/// std::runtime_error naming the file that is not DICOM (before anything is sent), or the
/// server's refusal (HTTP status, the SOP instances it lists as failed).
void StoreFilesWeb(const DicomWebServer& server, const std::vector<std::string>& files);

} // namespace bm
