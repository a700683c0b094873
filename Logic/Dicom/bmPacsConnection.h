// bmPacsConnection.h - a PACS named by one text, on either face: "[AET@]HOST:PORT" is DICOM's
// network protocol (DIMSE, bmPacsClient.h), an http:// or https:// root is DICOMweb
// (bmDicomWebClient.h). The text is parsed once, here; finding, fetching and storing then go to
// the face it names. bmsim pacs and the dock's PACS browser (qBMPacsBrowser) both use it.
//
// Units: s (timeouts).
#pragma once

#include <string>
#include <vector>

#include "bmDicomWebClient.h"
#include "bmPacsClient.h"

namespace bm {

class PacsConnection {
public:
  /// Parses `text`: a DICOMweb root (bm::IsDicomWebUrl; trailing slashes dropped) or
  /// "[AET@]HOST:PORT" (bm::ParsePacsServer: the called AET defaults to `base`'s). `base` also
  /// gives our calling AET (DIMSE only; default BMSIM) and the timeout of either face (s, in
  /// [1, 3600], default 30). Throws std::invalid_argument naming the text when it is neither.
  explicit PacsConnection(const std::string& text, const PacsServer& base = {});

  /// Whether the text named a DICOMweb root (else a DIMSE address).
  bool IsDicomWeb() const { return Web; }
  /// The server as errors name it: "AET@HOST:PORT" or the DICOMweb root.
  std::string Name() const;
  /// The DIMSE address (meaningful when !IsDicomWeb()).
  const PacsServer& Dimse() const { return DimseServer; }
  /// The DICOMweb root (meaningful when IsDicomWeb()).
  const DicomWebServer& DicomWeb() const { return WebServer; }

  /// The series matching `q` (C-FIND or QIDO-RS). Throws std::runtime_error as
  /// bm::FindSeries / bm::FindSeriesWeb do.
  std::vector<PacsSeries> FindSeries(const PacsQuery& q) const;
  /// One series into the new folder `folder` (C-GET or WADO-RS; the study found first when
  /// empty). Returns the instances written. Throws std::runtime_error, leaving no folder, as
  /// bm::GetSeries / bm::GetSeriesWeb do.
  int GetSeries(const std::string& studyInstanceUid, const std::string& seriesInstanceUid,
                const std::string& folder) const;
  /// DICOM files to the PACS (C-STORE or STOW-RS). Throws std::runtime_error as bm::StoreFiles /
  /// bm::StoreFilesWeb do.
  void StoreFiles(const std::vector<std::string>& files) const;

private:
  bool Web = false;
  PacsServer DimseServer;
  DicomWebServer WebServer;
};

} // namespace bm
