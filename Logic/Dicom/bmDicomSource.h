// bmDicomSource.h - the DICOM series a CT came from, as results written beside it need it: the
// patient, study and frame of reference to share, and the images to reference (DCMTK).
//
// Units: mm (DICOM patient coordinates, LPS).
#pragma once

#include <string>
#include <vector>

namespace bm {

/// One image of the source series.
struct DicomSourceImage {
  std::string file;           ///< path
  std::string sopInstanceUID; ///< SOPInstanceUID
  std::string sopClassUID;    ///< SOPClassUID
  double positionZ = 0;       ///< ImagePositionPatient z, mm
};

struct DicomSource {
  std::string folder;
  std::string seriesUID, studyUID, frameOfReferenceUID, modality, patientID;
  std::vector<DicomSourceImage> images; ///< by ImagePositionPatient z, then by file name
  /// The image whose ImagePositionPatient z is nearest to zMm (mm).
  const DicomSourceImage& NearestImage(double zMm) const;
};

/// The source series in a DICOM folder (seriesUID "" = its only image series). Reads the headers
/// only. Throws std::runtime_error naming the problem: not a folder, no DICOM image in it, several
/// series and none chosen (listing them), the chosen series absent, an image without
/// SOPInstanceUID, StudyInstanceUID or FrameOfReferenceUID (results could not share its frame).
DicomSource ReadDicomSource(const std::string& folder, const std::string& seriesUID = "");

} // namespace bm
