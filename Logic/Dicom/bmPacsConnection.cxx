#include "bmPacsConnection.h"

namespace bm {

PacsConnection::PacsConnection(const std::string& text, const PacsServer& base) {
  if (IsDicomWebUrl(text)) {
    Web = true;
    WebServer.url = text;
    while (!WebServer.url.empty() && WebServer.url.back() == '/')
      WebServer.url.pop_back();
    WebServer.timeoutS = base.timeoutS;
    return;
  }
  DimseServer = ParsePacsServer(text, base);
}

std::string PacsConnection::Name() const {
  if (Web)
    return WebServer.url;
  return DimseServer.calledAet + "@" + DimseServer.host + ":" + std::to_string(DimseServer.port);
}

std::vector<PacsSeries> PacsConnection::FindSeries(const PacsQuery& q) const {
  return Web ? FindSeriesWeb(WebServer, q) : bm::FindSeries(DimseServer, q);
}

int PacsConnection::GetSeries(const std::string& studyInstanceUid,
                              const std::string& seriesInstanceUid,
                              const std::string& folder) const {
  return Web ? GetSeriesWeb(WebServer, studyInstanceUid, seriesInstanceUid, folder)
             : bm::GetSeries(DimseServer, studyInstanceUid, seriesInstanceUid, folder);
}

void PacsConnection::StoreFiles(const std::vector<std::string>& files) const {
  if (Web)
    StoreFilesWeb(WebServer, files);
  else
    bm::StoreFiles(DimseServer, files);
}

} // namespace bm
