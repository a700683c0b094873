// bmDicomSegmentation.cxx - see bmDicomSegmentation.h.
#include "bmDicomSegmentation.h"

#include <memory>
#include <set>
#include <stdexcept>
#include <vector>

#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmfg/fgderimg.h>
#include <dcmtk/dcmfg/fgfracon.h>
#include <dcmtk/dcmfg/fgpixmsr.h>
#include <dcmtk/dcmfg/fgplanor.h>
#include <dcmtk/dcmfg/fgplanpo.h>
#include <dcmtk/dcmiod/iodmacro.h>
#include <dcmtk/dcmiod/iodreferences.h>
#include <dcmtk/dcmseg/segdoc.h>
#include <dcmtk/dcmseg/segment.h>

#include "bmDicomWriting.h"

namespace bm {

namespace {

void Check(const OFCondition& c, const std::string& what) {
  CheckDicom(c, "DICOM segmentation", what);
}

} // namespace

DicomSegmentationResult WriteReamingSegmentation(const std::string& path, const DicomSource& source,
                                                 const Voxmap& before, const Voxmap& after,
                                                 const DicomSegmentationInfo& info) {
  QuietDicomLog();
  if (before.Dims() != after.Dims() || before.Spacing() != after.Spacing() ||
      before.Origin() != after.Origin())
    throw std::invalid_argument("DICOM segmentation: the voxmaps before and after differ in grid");
  const auto& n = before.Dims();
  if (n[0] > 65535 || n[1] > 65535)
    throw std::invalid_argument("DICOM segmentation: a slice of " + std::to_string(n[0]) + " x " +
                                std::to_string(n[1]) + " cells is larger than DICOM allows");
  if (source.images.empty())
    throw std::invalid_argument("DICOM segmentation: the source series has no image");

  const std::string version = info.softwareVersion.empty() ? "unknown" : info.softwareVersion;
  IODGeneralEquipmentModule::EquipmentInfo equipment("BoneMachining", "0", "bmsim",
                                                     version.c_str());
  ContentIdentificationMacro content("1", "REAMING", "Bone before and after the plan's steps",
                                     "BoneMachining");
  DcmSegmentation* raw = nullptr;
  Check(DcmSegmentation::createBinarySegmentation(raw, Uint16(n[1]), Uint16(n[0]), equipment,
                                                  content),
        "create");
  std::unique_ptr<DcmSegmentation> seg(raw);
  Check(seg->importFromSourceImage(source.images.front().file.c_str()),
        "import patient, study and frame of reference from " + source.images.front().file);
  // Its own series in the source's study (the import takes the source's series over too).
  char seriesUID[100];
  Check(seg->getSeries().setSeriesInstanceUID(dcmGenerateUniqueIdentifier(seriesUID)),
        "series UID");
  seg->getSeries().setModality("SEG");
  seg->getSeries().setSeriesDescription(info.seriesDescription.c_str());
  seg->getSeries().setSeriesNumber(std::to_string(info.seriesNumber).c_str());

  const CodeSequenceMacro tissue("85756007", "SCT", "Tissue");
  const CodeSequenceMacro bone("272673000", "SCT", "Bone");
  Uint16 numbers[2] = {0, 0};
  const char* labels[2] = {"Bone removed", "Bone remaining"};
  for (int s = 0; s < 2; ++s) {
    DcmSegment* segment = nullptr;
    Check(DcmSegment::create(segment, labels[s], tissue, bone, DcmSegTypes::SAT_AUTOMATIC,
                             "BoneMachining reaming simulation"),
          "segment");
    Check(seg->addSegment(segment, numbers[s]), "add segment");
  }

  // Shared: the slices' orientation (x columns, y rows) and pixel measures.
  const double h = before.Spacing();
  const std::unique_ptr<FGPlaneOrientationPatient> orient(
      FGPlaneOrientationPatient::createMinimal("1", "0", "0", "0", "1", "0"));
  if (!orient)
    throw std::runtime_error("DICOM segmentation: cannot make the plane orientation");
  FGPixelMeasures pixels;
  std::string spacing = DicomDecimal(h);
  spacing += '\\';
  spacing += DicomDecimal(h);
  pixels.setPixelSpacing(spacing.c_str());
  pixels.setSliceThickness(DicomDecimal(h).c_str());
  pixels.setSpacingBetweenSlices(DicomDecimal(h).c_str());
  Check(seg->addForAllFrames(*orient), "plane orientation");
  Check(seg->addForAllFrames(pixels), "pixel measures");

  // Frames are indexed by segment, then by their slice's position.
  char dimUID[100];
  dcmGenerateUniqueIdentifier(dimUID);
  IODMultiframeDimensionModule& dims = seg->getDimensions();
  Check(dims.addDimensionIndex(DCM_ReferencedSegmentNumber, dimUID,
                               DCM_SegmentIdentificationSequence, "ReferencedSegmentNumber"),
        "dimension: segment");
  Check(dims.addDimensionIndex(DCM_ImagePositionPatient, dimUID, DCM_PlanePositionSequence,
                               "ImagePositionPatient"),
        "dimension: position");

  DicomSegmentationResult result;
  std::set<const DicomSourceImage*> referenced;
  std::vector<Uint8> frame(size_t(n[0]) * size_t(n[1]));
  const CodeSequenceMacro derivation("113076", "DCM", "Segmentation");
  const CodeSequenceMacro purpose("121322", "DCM", "Source image for image processing operation");
  for (int k = 0; k < n[2]; ++k) {
    const auto o = before.GridToWorld({0.0, 0.0, double(k)});
    for (int s = 0; s < 2; ++s) {
      bool any = false;
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const int64_t idx = before.Index(i, j, k);
          const bool wasBone = before.Fraction(idx) >= 0.5, isBone = after.Fraction(idx) >= 0.5;
          const bool in = s == 0 ? (wasBone && !isBone) : isBone;
          frame[size_t(j) * size_t(n[0]) + size_t(i)] = in ? 1 : 0;
          any |= in;
        }
      if (!any)
        continue;
      const std::unique_ptr<FGPlanePosPatient> pos(FGPlanePosPatient::createMinimal(
          DicomDecimal(o[0]).c_str(), DicomDecimal(o[1]).c_str(), DicomDecimal(o[2]).c_str()));
      const DicomSourceImage& near = source.NearestImage(o[2]);
      referenced.insert(&near);
      ImageSOPInstanceReferenceMacro ref;
      ref.setReferencedSOPClassUID(near.sopClassUID.c_str());
      ref.setReferencedSOPInstanceUID(near.sopInstanceUID.c_str());
      OFVector<ImageSOPInstanceReferenceMacro> refs;
      refs.push_back(ref);
      const std::unique_ptr<FGDerivationImage> der(FGDerivationImage::createMinimal(
          refs, "Bone voxmap resampled from the CT and cut by the plan's steps", derivation,
          purpose));
      if (!pos || !der)
        throw std::runtime_error("DICOM segmentation: cannot make frame " + std::to_string(k) +
                                 "'s position or derivation");
      FGFrameContent content;
      content.setDimensionIndexValues(numbers[s], 0);
      content.setDimensionIndexValues(Uint32(k + 1), 1);
      OFVector<FGBase*> perFrame;
      perFrame.push_back(pos.get());
      perFrame.push_back(der.get());
      perFrame.push_back(&content);
      Check(seg->addFrame(frame.data(), numbers[s], perFrame), "frame " + std::to_string(k));
      (s == 0 ? result.removedFrames : result.remainingFrames)++;
    }
  }
  if (result.removedFrames + result.remainingFrames == 0)
    throw std::runtime_error("DICOM segmentation: no bone before or after: nothing to write");
  // The source images the frames derive from (Common Instance Reference).
  IODReferences refs;
  for (const DicomSourceImage* im : referenced)
    refs.add(new IODImageReference(source.patientID.c_str(), source.studyUID.c_str(),
                                   source.seriesUID.c_str(), im->sopInstanceUID.c_str(),
                                   im->sopClassUID.c_str()));
  if (seg->getCommonInstanceReference().addReferences(refs, source.studyUID.c_str()) !=
      referenced.size())
    throw std::runtime_error("DICOM segmentation: cannot reference the source images");

  SaveDicomAtomically(path, "DICOM segmentation", [&](const std::string& tmp) {
    const OFCondition c = seg->saveFile(tmp.c_str());
    return c.good() ? std::string() : std::string(c.text());
  });
  OFString uid;
  seg->getSOPCommon().getSOPInstanceUID(uid);
  result.sopInstanceUID = uid.c_str();
  seg->getSeries().getSeriesInstanceUID(uid);
  result.seriesUID = uid.c_str();
  return result;
}

} // namespace bm
