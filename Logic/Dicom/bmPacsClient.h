// bmPacsClient.h - a PACS over DICOM's network protocol (DIMSE, DCMTK's DcmSCU): find a
// patient's CT series (C-FIND, Study Root, series level), fetch one into a folder (C-GET) and send
// files back (C-STORE), Docs/Dicom.md "PACS".
//
// Every call opens its own association and releases it (aborts it on an error), so a server that
// is down, slow, refuses the association or returns a broken series gets a std::runtime_error
// naming the server, the step and DCMTK's or the server's reason. A fetched series is written
// under a temporary sibling of the target folder and renamed onto it only when every instance
// arrived: a failed fetch leaves nothing.
//
// Units: s (timeouts).
#pragma once

#include <string>
#include <vector>

namespace bm {

/// Where the PACS is and who we are to it.
struct PacsServer {
  std::string host = "127.0.0.1";
  int port = 4242;                   ///< its DICOM port, in [1, 65535]
  std::string calledAet = "ORTHANC"; ///< its application entity title (1-16 characters)
  std::string callingAet = "BMSIM";  ///< ours, as the PACS knows us (1-16 characters)
  int timeoutS = 30;                 ///< connection and each message's timeout, s, in [1, 3600]
};

/// Parses "AET@host:port" (the AET optional: "host:port" keeps `base`'s). Throws
/// std::invalid_argument naming the text when it is not that shape or the port is out of range.
PacsServer ParsePacsServer(const std::string& text, const PacsServer& base = {});

/// A series on a PACS as one text: pacs://[AET@]HOST:PORT/SERIES-UID[?aet=OURS] (the called AET
/// defaults to `base`'s, ours too unless given). Throws std::invalid_argument naming the text
/// when it is not that shape.
struct PacsSeriesUrl {
  PacsServer server;
  std::string seriesInstanceUid;
};
PacsSeriesUrl ParsePacsUrl(const std::string& url, const PacsServer& base = {});

/// What to look for; empty fields match anything. DICOM wildcards (* and ?) are allowed in the
/// patient's name and ID.
struct PacsQuery {
  std::string patientId, patientName, accessionNumber, studyInstanceUid, seriesInstanceUid;
  std::string modality = "CT"; ///< "" for any
};

/// One series the PACS holds.
struct PacsSeries {
  std::string patientId, patientName, studyInstanceUid, studyDate, accessionNumber;
  std::string seriesInstanceUid, modality, seriesDescription;
  int instances = -1; ///< number of series related instances, -1 when the PACS does not say
};

/// C-FIND (Study Root, SERIES level): the series matching `q`, in the PACS's order. Throws
/// std::runtime_error when the server cannot be reached, refuses the association or the query,
/// or answers with a failure status.
std::vector<PacsSeries> FindSeries(const PacsServer& server, const PacsQuery& q);

/// C-GET of one series into `folder` (created; it must not exist yet), one file per instance
/// (named by SOP Instance UID). Returns the number of instances written. Throws
/// std::runtime_error (and leaves no folder) when the series is unknown or empty, an instance
/// fails or does not arrive, the server refuses or times out.
int GetSeries(const PacsServer& server, const std::string& studyInstanceUid,
              const std::string& seriesInstanceUid, const std::string& folder);

/// C-STORE of DICOM files (any storage SOP class: CT images, a Segmentation, a Structured
/// Report). Throws std::runtime_error naming the file when one cannot be read or the server
/// refuses it; files before it were stored.
void StoreFiles(const PacsServer& server, const std::vector<std::string>& files);

} // namespace bm
