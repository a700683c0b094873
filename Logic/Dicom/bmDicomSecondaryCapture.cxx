#include "bmDicomSecondaryCapture.h"

#include "bmDicomWriting.h"

#include <dcmtk/config/osconfig.h>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/ofstd/ofdatime.h>

#include <png.h>

#include <memory>
#include <stdexcept>
#include <vector>

namespace bm {

namespace {

constexpr unsigned kMaxSide = 16384;

struct Rgb {
  unsigned width = 0, height = 0;
  std::vector<unsigned char> pixels; ///< rows top to bottom, R G B
};

Rgb ReadPng(const std::string& file) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, file.c_str()))
    throw std::runtime_error("picture '" + file + "' cannot be read as a PNG: " + image.message);
  if (image.width == 0 || image.height == 0 || image.width > kMaxSide || image.height > kMaxSide) {
    png_image_free(&image);
    throw std::runtime_error("picture '" + file + "' is " + std::to_string(image.width) + " x " +
                             std::to_string(image.height) + " pixels (1 to " +
                             std::to_string(kMaxSide) + " a side)");
  }
  image.format = PNG_FORMAT_RGB;
  Rgb out;
  out.width = image.width;
  out.height = image.height;
  out.pixels.resize(size_t(PNG_IMAGE_SIZE(image)));
  if (!png_image_finish_read(&image, nullptr, out.pixels.data(), 0, nullptr))
    throw std::runtime_error("picture '" + file + "' cannot be decoded: " + image.message);
  return out;
}

std::string NewUid() {
  char uid[100];
  return dcmGenerateUniqueIdentifier(uid, SITE_INSTANCE_UID_ROOT);
}

} // namespace

std::string WriteSecondaryCapture(const std::string& path, const DicomSource& source,
                                  const std::string& png, const DicomPictureInfo& info) {
  QuietDicomLog();
  if (source.images.empty())
    throw std::runtime_error("secondary capture: the source series has no image");
  const Rgb picture = ReadPng(png);
  const std::string what = "secondary capture";
  DcmFileFormat ff;
  DcmDataset& d = *ff.getDataset();
  // The source's patient and study, as the PACS files them.
  DcmFileFormat src;
  CheckDicom(src.loadFileUntilTag(source.images.front().file.c_str(), EXS_Unknown, EGL_noChange,
                                  DCM_MaxReadLength, ERM_autoDetect, DCM_PixelData),
             what, "read " + source.images.front().file);
  for (const DcmTagKey& tag :
       {DCM_PatientName, DCM_PatientID, DCM_PatientBirthDate, DCM_PatientSex, DCM_StudyDate,
        DCM_StudyTime, DCM_StudyID, DCM_AccessionNumber, DCM_ReferringPhysicianName,
        DCM_StudyDescription, DCM_SpecificCharacterSet}) {
    OFString v;
    if (src.getDataset()->findAndGetOFStringArray(tag, v).good())
      d.putAndInsertOFStringArray(tag, v);
    else if (tag != DCM_StudyDescription && tag != DCM_SpecificCharacterSet)
      d.putAndInsertOFStringArray(tag, ""); // type 2: present, empty
  }
  const std::string sop = NewUid();
  OFString date, time;
  OFDateTime::getCurrentDateTime().getDate().getISOFormattedDate(date, false);
  OFDateTime::getCurrentDateTime().getTime().getISOFormattedTime(time, true, false, false, false);
  const auto put = [&](const DcmTagKey& tag, const std::string& v) {
    CheckDicom(d.putAndInsertOFStringArray(tag, v.c_str()), what,
               std::string("set ") + tag.toString().c_str());
  };
  put(DCM_SOPClassUID, UID_SecondaryCaptureImageStorage);
  put(DCM_SOPInstanceUID, sop);
  put(DCM_StudyInstanceUID, source.studyUID);
  put(DCM_SeriesInstanceUID, info.seriesUID.empty() ? NewUid() : info.seriesUID);
  put(DCM_Modality, "OT");
  put(DCM_Laterality, ""); // type 2C: the shoulder's side is the CT's, not said again here
  put(DCM_SeriesNumber, std::to_string(info.seriesNumber));
  put(DCM_SeriesDescription, "BoneMachining plan pictures");
  put(DCM_InstanceNumber, std::to_string(info.instanceNumber));
  put(DCM_PatientOrientation, "");
  put(DCM_ContentDate, date.c_str());
  put(DCM_ContentTime, time.c_str());
  put(DCM_ConversionType, "WSD"); // a workstation's picture
  put(DCM_Manufacturer, "BoneMachining");
  if (!info.softwareVersion.empty())
    put(DCM_SoftwareVersions, info.softwareVersion);
  put(DCM_ImageType, "DERIVED\\SECONDARY");
  put(DCM_DerivationDescription, "Rendered from the bone model of the CT series " +
                                     source.seriesUID + ": " + info.description);
  put(DCM_ImageComments, info.description);
  put(DCM_BurnedInAnnotation, "NO");
  CheckDicom(d.putAndInsertUint16(DCM_SamplesPerPixel, 3), what, "samples");
  put(DCM_PhotometricInterpretation, "RGB");
  CheckDicom(d.putAndInsertUint16(DCM_PlanarConfiguration, 0), what, "planar configuration");
  CheckDicom(d.putAndInsertUint16(DCM_Rows, Uint16(picture.height)), what, "rows");
  CheckDicom(d.putAndInsertUint16(DCM_Columns, Uint16(picture.width)), what, "columns");
  CheckDicom(d.putAndInsertUint16(DCM_BitsAllocated, 8), what, "bits");
  CheckDicom(d.putAndInsertUint16(DCM_BitsStored, 8), what, "bits");
  CheckDicom(d.putAndInsertUint16(DCM_HighBit, 7), what, "bits");
  CheckDicom(d.putAndInsertUint16(DCM_PixelRepresentation, 0), what, "pixel representation");
  CheckDicom(d.putAndInsertUint8Array(DCM_PixelData, picture.pixels.data(),
                                      static_cast<unsigned long>(picture.pixels.size())),
             what, "pixels");
  SaveDicomAtomically(path, "DICOM secondary capture", [&](const std::string& tmp) {
    const OFCondition c = ff.saveFile(tmp.c_str(), EXS_LittleEndianExplicit);
    return c.good() ? std::string() : std::string(c.text());
  });
  return sop;
}

} // namespace bm
