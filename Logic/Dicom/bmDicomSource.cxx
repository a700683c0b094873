// bmDicomSource.cxx - see bmDicomSource.h.
#include "bmDicomSource.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>

#include "bmDicomWriting.h"

namespace bm {

namespace {

std::string Text(DcmDataset& d, const DcmTagKey& tag) {
  OFString v;
  if (d.findAndGetOFStringArray(tag, v).good())
    return std::string(v.c_str());
  return "";
}

} // namespace

const DicomSourceImage& DicomSource::NearestImage(double zMm) const {
  if (images.empty())
    throw std::runtime_error("DICOM source " + folder + ": no image");
  return *std::min_element(images.begin(), images.end(), [&](const auto& a, const auto& b) {
    return std::abs(a.positionZ - zMm) < std::abs(b.positionZ - zMm);
  });
}

DicomSource ReadDicomSource(const std::string& folder, const std::string& seriesUID) {
  QuietDicomLog();
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error("DICOM source '" + folder + "' is not a folder");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (e.is_regular_file(ec))
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::map<std::string, DicomSource> series;
  for (const fs::path& f : files) {
    DcmFileFormat ff;
    // Headers only: stop before the pixel data.
    if (ff.loadFileUntilTag(f.c_str(), EXS_Unknown, EGL_noChange, DCM_MaxReadLength, ERM_autoDetect,
                            DCM_PixelData)
            .bad())
      continue; // not DICOM (a DICOMDIR's neighbours, a README)
    DcmDataset& d = *ff.getDataset();
    const std::string uid = Text(d, DCM_SeriesInstanceUID);
    if (uid.empty() || Text(d, DCM_Rows).empty())
      continue; // not an image of a series
    DicomSource& s = series[uid];
    s.folder = folder;
    s.seriesUID = uid;
    s.studyUID = Text(d, DCM_StudyInstanceUID);
    s.frameOfReferenceUID = Text(d, DCM_FrameOfReferenceUID);
    s.modality = Text(d, DCM_Modality);
    s.patientID = Text(d, DCM_PatientID);
    DicomSourceImage im;
    im.file = f.string();
    im.sopInstanceUID = Text(d, DCM_SOPInstanceUID);
    im.sopClassUID = Text(d, DCM_SOPClassUID);
    Float64 z = 0;
    if (d.findAndGetFloat64(DCM_ImagePositionPatient, z, 2).bad())
      z = 0;
    im.positionZ = z;
    if (im.sopInstanceUID.empty() || im.sopClassUID.empty())
      throw std::runtime_error("DICOM source " + im.file + ": no SOPInstanceUID or SOPClassUID");
    if (s.studyUID.empty() || s.frameOfReferenceUID.empty())
      throw std::runtime_error("DICOM source " + im.file +
                               ": no StudyInstanceUID or FrameOfReferenceUID (results could not "
                               "share the image's patient frame)");
    s.images.push_back(im);
  }
  if (series.empty())
    throw std::runtime_error("DICOM source '" + folder + "' holds no DICOM image series");
  const DicomSource* chosen = nullptr;
  if (seriesUID.empty()) {
    if (series.size() > 1) {
      std::string list;
      for (const auto& [uid, s] : series) {
        if (!list.empty())
          list += ", ";
        list += uid;
        list += " (";
        list += std::to_string(s.images.size());
        list += " images)";
      }
      throw std::runtime_error("DICOM source '" + folder + "' holds " +
                               std::to_string(series.size()) + " series: choose one of " + list);
    }
    chosen = &series.begin()->second;
  } else {
    const auto it = series.find(seriesUID);
    if (it == series.end())
      throw std::runtime_error("DICOM source '" + folder + "' has no series " + seriesUID);
    chosen = &it->second;
  }
  DicomSource out = *chosen;
  std::stable_sort(out.images.begin(), out.images.end(),
                   [](const auto& a, const auto& b) { return a.positionZ < b.positionZ; });
  return out;
}

} // namespace bm
