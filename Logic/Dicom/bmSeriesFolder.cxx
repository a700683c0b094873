#include "bmSeriesFolder.h"

#include "bmPacsConnection.h"

#include <dcmtk/config/osconfig.h>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>

#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace bm {

std::string SeriesFolder(const std::string& parent, const std::string& seriesInstanceUid) {
  if (seriesInstanceUid.empty())
    throw std::invalid_argument("a series folder needs a Series Instance UID");
  std::string name = seriesInstanceUid;
  for (char& ch : name)
    if (!std::isdigit(static_cast<unsigned char>(ch)) && ch != '.')
      ch = '_';
  if (name == "." || name == "..")
    name = "_";
  return (fs::path(parent) / name).string();
}

int HeldSeriesInstances(const std::string& folder, const std::string& seriesInstanceUid) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    return -1;
  int held = 0;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec))
      return 0;
    // Values longer than DCM_MaxReadLength (the pixel data) stay in the file.
    DcmFileFormat file;
    if (file.loadFile(it->path().string().c_str()).bad())
      return 0;
    OFString uid;
    if (file.getDataset()->findAndGetOFString(DCM_SeriesInstanceUID, uid).bad() ||
        seriesInstanceUid != uid.c_str())
      return 0;
    ++held;
  }
  return ec ? 0 : held;
}

SeriesFetch FetchSeriesInto(const PacsConnection& pacs, const PacsSeries& series,
                            const std::string& folder) {
  SeriesFetch fetch;
  const int held = HeldSeriesInstances(folder, series.seriesInstanceUid);
  if (held > 0 && (series.instances < 0 || held == series.instances)) {
    fetch.instances = held;
    fetch.reused = true;
    return fetch;
  }
  if (held >= 0)
    throw std::runtime_error(
        "'" + folder + "' exists and does not hold series " + series.seriesInstanceUid +
        " whole (" + std::to_string(held) + " of its " +
        (series.instances >= 0 ? std::to_string(series.instances) : std::string("?")) +
        " instances): remove it or fetch into another folder");
  fetch.instances = pacs.GetSeries(series.studyInstanceUid, series.seriesInstanceUid, folder);
  return fetch;
}

} // namespace bm
