// bmDicomMeasurementReport.cxx - see bmDicomMeasurementReport.h.
#include "bmDicomMeasurementReport.h"

#include <cmath>
#include <stdexcept>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmsr/dsrdoc.h>
#include <dcmtk/dcmsr/dsrimgvl.h>
#include <dcmtk/dcmsr/dsrnumvl.h>

#include "bmDicomWriting.h"

namespace bm {

namespace {

void Check(const OFCondition& c, const std::string& what) {
  CheckDicom(c, "DICOM measurement report", what);
}

const char* const kScheme = "99BMSIM";

} // namespace

std::string WriteMeasurementReport(const std::string& path, const DicomSource& source,
                                   const std::vector<DicomMeasurement>& measurements,
                                   const DicomReportInfo& info) {
  QuietDicomLog();
  if (measurements.empty())
    throw std::invalid_argument("DICOM measurement report: no measurement");
  for (const DicomMeasurement& m : measurements)
    if (m.code.empty() || m.code.size() > 16 || m.name.empty() || m.name.size() > 64 ||
        !std::isfinite(m.value) || m.unit.empty())
      throw std::invalid_argument("DICOM measurement report: measurement '" + m.name +
                                  "' needs a code of 1-16 characters, a name of 1-64, a finite "
                                  "value and a unit");
  if (source.images.empty())
    throw std::invalid_argument("DICOM measurement report: the source series has no image");

  DSRDocument doc(DSRTypes::DT_ComprehensiveSR);
  Check(doc.createNewSeriesInStudy(source.studyUID.c_str()), "series in the source's study");
  doc.setSeriesDescription(info.seriesDescription.c_str());
  doc.setSeriesNumber(std::to_string(info.seriesNumber).c_str());
  doc.setManufacturer("BoneMachining");
  doc.setManufacturerModelName("bmsim");
  DSRDocumentTree& tree = doc.getTree();
  auto add = [&](DSRTypes::E_RelationshipType rel, DSRTypes::E_ValueType type,
                 const DSRCodedEntryValue& name, bool below) {
    if (tree.addContentItem(rel, type,
                            below ? DSRTypes::AM_belowCurrent : DSRTypes::AM_afterCurrent) == 0)
      throw std::runtime_error("DICOM measurement report: cannot add " +
                               std::string(name.getCodeMeaning().c_str()));
    Check(tree.getCurrentContentItem().setConceptName(name), "concept");
  };
  add(DSRTypes::RT_isRoot, DSRTypes::VT_Container,
      DSRCodedEntryValue("126000", "DCM", "Imaging Measurement Report"), false);
  add(DSRTypes::RT_hasConceptMod, DSRTypes::VT_Code,
      DSRCodedEntryValue("121049", "DCM", "Language of Content Item and Descendants"), true);
  Check(tree.getCurrentContentItem().setCodeValue(
            DSRCodedEntryValue("en-US", "RFC5646", "English (United States)")),
        "language");
  add(DSRTypes::RT_hasObsContext, DSRTypes::VT_Code,
      DSRCodedEntryValue("121005", "DCM", "Observer Type"), false);
  Check(tree.getCurrentContentItem().setCodeValue(DSRCodedEntryValue("121007", "DCM", "Device")),
        "observer type");
  add(DSRTypes::RT_hasObsContext, DSRTypes::VT_UIDRef,
      DSRCodedEntryValue("121012", "DCM", "Device Observer UID"), false);
  char uid[100];
  Check(tree.getCurrentContentItem().setStringValue(dcmGenerateUniqueIdentifier(uid)),
        "device UID");
  add(DSRTypes::RT_hasObsContext, DSRTypes::VT_Text,
      DSRCodedEntryValue("121013", "DCM", "Device Observer Name"), false);
  Check(tree.getCurrentContentItem().setStringValue("BoneMachining"), "device name");

  // The source images.
  add(DSRTypes::RT_contains, DSRTypes::VT_Container,
      DSRCodedEntryValue("111028", "DCM", "Image Library"), false);
  add(DSRTypes::RT_contains, DSRTypes::VT_Container,
      DSRCodedEntryValue("126200", "DCM", "Image Library Group"), true);
  bool first = true;
  size_t libraryGroup = tree.getNodeID();
  for (const DicomSourceImage& im : source.images) {
    if (tree.addContentItem(DSRTypes::RT_contains, DSRTypes::VT_Image,
                            first ? DSRTypes::AM_belowCurrent : DSRTypes::AM_afterCurrent) == 0)
      throw std::runtime_error("DICOM measurement report: cannot add an image reference");
    Check(tree.getCurrentContentItem().setImageReference(
              DSRImageReferenceValue(im.sopClassUID.c_str(), im.sopInstanceUID.c_str()), false),
          "image reference " + im.sopInstanceUID);
    first = false;
  }
  tree.gotoNode(libraryGroup);
  tree.goUp(); // the image library

  add(DSRTypes::RT_contains, DSRTypes::VT_Container,
      DSRCodedEntryValue("126010", "DCM", "Imaging Measurements"), false);
  add(DSRTypes::RT_contains, DSRTypes::VT_Container,
      DSRCodedEntryValue("125007", "DCM", "Measurement Group"), true);
  add(DSRTypes::RT_hasObsContext, DSRTypes::VT_Text,
      DSRCodedEntryValue("112039", "DCM", "Tracking Identifier"), true);
  Check(tree.getCurrentContentItem().setStringValue(info.title.c_str()), "tracking identifier");
  add(DSRTypes::RT_hasObsContext, DSRTypes::VT_UIDRef,
      DSRCodedEntryValue("112040", "DCM", "Tracking Unique Identifier"), false);
  Check(tree.getCurrentContentItem().setStringValue(dcmGenerateUniqueIdentifier(uid)),
        "tracking UID");
  for (const DicomMeasurement& m : measurements) {
    add(DSRTypes::RT_contains, DSRTypes::VT_Num,
        DSRCodedEntryValue(m.code.c_str(), kScheme, m.name.c_str()), false);
    Check(
        tree.getCurrentContentItem().setNumericValue(
            DSRNumericMeasurementValue(DicomDecimal(m.value).c_str(),
                                       DSRCodedEntryValue(m.unit.c_str(), "UCUM", m.unit.c_str())),
            false),
        m.name);
    const size_t num = tree.getNodeID();
    if (!m.method.empty()) {
      add(DSRTypes::RT_hasConceptMod, DSRTypes::VT_Text,
          DSRCodedEntryValue("370129005", "SCT", "Measurement Method"), true);
      Check(tree.getCurrentContentItem().setStringValue(m.method.c_str(), false), "method");
    }
    tree.gotoNode(num);
  }

  // The evidence: every source image the library references.
  for (const DicomSourceImage& im : source.images)
    Check(doc.getCurrentRequestedProcedureEvidence().addItem(
              source.studyUID.c_str(), source.seriesUID.c_str(), im.sopClassUID.c_str(),
              im.sopInstanceUID.c_str()),
          "evidence " + im.sopInstanceUID);
  DcmFileFormat ff;
  Check(doc.write(*ff.getDataset()), "encode");
  // The source's patient and study, as the PACS files them.
  DcmFileFormat src;
  Check(src.loadFileUntilTag(source.images.front().file.c_str(), EXS_Unknown, EGL_noChange,
                             DCM_MaxReadLength, ERM_autoDetect, DCM_PixelData),
        "read " + source.images.front().file);
  for (const DcmTagKey& tag : {DCM_PatientName, DCM_PatientID, DCM_PatientBirthDate, DCM_PatientSex,
                               DCM_StudyDate, DCM_StudyTime, DCM_StudyID, DCM_AccessionNumber,
                               DCM_ReferringPhysicianName, DCM_StudyDescription}) {
    OFString v;
    if (src.getDataset()->findAndGetOFStringArray(tag, v).good())
      ff.getDataset()->putAndInsertOFStringArray(tag, v);
  }

  SaveDicomAtomically(path, "DICOM measurement report", [&](const std::string& tmp) {
    const OFCondition c = ff.saveFile(tmp.c_str(), EXS_LittleEndianExplicit);
    return c.good() ? std::string() : std::string(c.text());
  });
  OFString sop;
  doc.getSOPInstanceUID(sop);
  return sop.c_str();
}

} // namespace bm
