// Results as DICOM beside their CT (bmDicomSource.h, bmDicomSegmentation.h,
// bmDicomMeasurementReport.h): a small CT written as a real DICOM series (bmDicomSeriesWriter.h),
// a bone block before and after a hole is cut in it, the SEG and SR written and read back with
// DCMTK: patient, study and frame of reference are the source's, each frame references a source
// image of the series, the removed and remaining voxels come back where they were, the SR's values
// with their units; both pass dciodvfy (dicom3tools) where it is installed; bad input is refused
// and nothing is left half-written.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <filesystem>
#include <set>
#include <string>

#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcfilefo.h>
#include <dcmtk/dcmdata/dcuid.h>
#include <dcmtk/dcmfg/fgderimg.h>
#include <dcmtk/dcmfg/fgplanpo.h>
#include <dcmtk/dcmfg/fgseg.h>
#include <dcmtk/dcmseg/segdoc.h>
#include <dcmtk/dcmsr/dsrdoc.h>

#include "bmCTImage.h"
#include "bmDicomMeasurementReport.h"
#include "bmDicomSecondaryCapture.h"
#include "bmDicomSegmentation.h"
#include "bmDicomSeriesWriter.h"
#include "bmDicomSource.h"

namespace fs = std::filesystem;

namespace {

// The CT: 24 x 20 x 16 voxels of 1 mm from (-12, -10, 4) mm, world-aligned.
bm::CTImage SmallCT() {
  bm::CTImage ct;
  ct.hu = bm::HUImage::New();
  bm::HUImage::RegionType region;
  region.SetSize({{24, 20, 16}});
  ct.hu->SetRegions(region);
  bm::HUImage::SpacingType spacing;
  spacing.Fill(1.0);
  ct.hu->SetSpacing(spacing);
  bm::HUImage::PointType origin;
  origin[0] = -12;
  origin[1] = -10;
  origin[2] = 4;
  ct.hu->SetOrigin(origin);
  ct.hu->Allocate();
  ct.hu->FillBuffer(1000.0f);
  return ct;
}

fs::path Scratch(const std::string& name) {
  const fs::path d = fs::path(testing::TempDir()) / ("bm-dicom-" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// The bone: a 10 x 8 x 6 mm block at 0.5 mm voxels; after: a 2 x 2 mm hole through it.
struct Bones {
  bm::Voxmap before, after;
  int64_t removed = 0, remaining = 0;
  Bones() : before({24, 20, 16}, 0.5, {-5.75, -4.75, 6.25}), after(before) {
    const auto& n = before.Dims();
    for (int k = 2; k < 14; ++k)
      for (int j = 2; j < 18; ++j)
        for (int i = 2; i < 22; ++i) {
          const int64_t idx = before.Index(i, j, k);
          before.SetFill(idx, bm::Voxmap::kFull);
          const bool hole = i >= 10 && i < 14 && j >= 8 && j < 12;
          after.SetFill(idx, hole ? 0 : bm::Voxmap::kFull);
          (hole ? removed : remaining)++;
        }
    (void)n;
  }
};

std::string Text(DcmItem& d, const DcmTagKey& tag) {
  OFString v;
  d.findAndGetOFStringArray(tag, v); // this item only, not its sequences
  return v.c_str();
}

// dciodvfy's verdict: its error lines, or "" (none, or the tool is not installed).
std::string DciodvfyErrors(const std::string& file) {
  if (!fs::exists("/usr/bin/dciodvfy"))
    return "";
  const std::string log = file + ".dciodvfy";
  const int rc = std::system(("/usr/bin/dciodvfy '" + file + "' > '" + log + "' 2>&1").c_str());
  (void)rc;
  std::ifstream in(log);
  std::string line, errors;
  while (std::getline(in, line))
    if (line.rfind("Error", 0) == 0)
      errors += line + "\n";
  return errors;
}

} // namespace

TEST(DicomResults, SegmentationAndReportBesideTheirCT) {
  const fs::path dir = Scratch("results");
  bm::DicomWriteOptions wo;
  wo.patientID = "BM-TEST-7";
  const std::string seriesUID = bm::WriteDicomSeries(SmallCT(), (dir / "ct").string(), wo);
  const bm::DicomSource src = bm::ReadDicomSource((dir / "ct").string());
  ASSERT_EQ(src.images.size(), 16u);
  EXPECT_EQ(src.seriesUID, seriesUID);
  EXPECT_FALSE(src.frameOfReferenceUID.empty());
  EXPECT_DOUBLE_EQ(src.images.front().positionZ, 4.0);
  EXPECT_DOUBLE_EQ(src.NearestImage(9.4).positionZ, 9.0);

  const Bones b;
  const std::string segPath = (dir / "reamed-bone.seg.dcm").string();
  const bm::DicomSegmentationResult r =
      bm::WriteReamingSegmentation(segPath, src, b.before, b.after);
  EXPECT_EQ(r.removedFrames, 12);   // the hole's 12 slices
  EXPECT_EQ(r.remainingFrames, 12); // the block's
  EXPECT_TRUE(DciodvfyErrors(segPath).empty()) << DciodvfyErrors(segPath);

  // Read back: the source's patient, study and frame of reference; the voxels where they were.
  DcmFileFormat ff;
  ASSERT_TRUE(ff.loadFile(segPath.c_str()).good());
  DcmDataset& d = *ff.getDataset();
  EXPECT_EQ(Text(d, DCM_PatientID), "BM-TEST-7");
  EXPECT_EQ(Text(d, DCM_FrameOfReferenceUID), src.frameOfReferenceUID);
  EXPECT_EQ(Text(d, DCM_StudyInstanceUID), src.studyUID);
  EXPECT_NE(Text(d, DCM_SeriesInstanceUID), src.seriesUID);
  DcmSegmentation* raw = nullptr;
  ASSERT_TRUE(DcmSegmentation::loadFile(segPath.c_str(), raw).good());
  std::unique_ptr<DcmSegmentation> seg(raw);
  ASSERT_EQ(seg->getNumberOfSegments(), 2u);
  ASSERT_EQ(seg->getNumberOfFrames(), 24u);
  std::set<std::string> sources;
  for (const auto& im : src.images)
    sources.insert(im.sopInstanceUID);
  int64_t counted[2] = {0, 0};
  FGInterface& fg = seg->getFunctionalGroups();
  for (Uint32 f = 0; f < 24; ++f) {
    const DcmIODTypes::Frame* frame = seg->getFrame(f);
    ASSERT_NE(frame, nullptr);
    FGSegmentation* fs = OFstatic_cast(FGSegmentation*, fg.get(f, DcmFGTypes::EFG_SEGMENTATION));
    ASSERT_NE(fs, nullptr);
    Uint16 segment = 0;
    fs->getReferencedSegmentNumber(segment);
    FGPlanePosPatient* pos =
        OFstatic_cast(FGPlanePosPatient*, fg.get(f, DcmFGTypes::EFG_PLANEPOSPATIENT));
    ASSERT_NE(pos, nullptr);
    Float64 x = 0, y = 0, z = 0;
    pos->getImagePositionPatient(x, y, z);
    const int k = int(std::lround((z - 6.25) / 0.5));
    EXPECT_TRUE(k >= 2 && k < 14) << z;
    FGDerivationImage* der =
        OFstatic_cast(FGDerivationImage*, fg.get(f, DcmFGTypes::EFG_DERIVATIONIMAGE));
    ASSERT_NE(der, nullptr);
    OFString refUID;
    der->getDerivationImageItems()[0]
        ->getSourceImageItems()[0]
        ->getImageSOPInstanceReference()
        .getReferencedSOPInstanceUID(refUID);
    EXPECT_EQ(sources.count(refUID.c_str()), 1u) << refUID;
    // Binary frames are bit-packed, first pixel in the lowest bit.
    for (size_t p = 0; p < size_t(24 * 20); ++p)
      counted[segment - 1] += (frame->pixData[p / 8] >> (p % 8)) & 1;
  }
  EXPECT_EQ(counted[0], b.removed);
  EXPECT_EQ(counted[1], b.remaining);

  // The report.
  const std::string srPath = (dir / "plan.sr.dcm").string();
  const std::vector<bm::DicomMeasurement> m = {
      {"version-3d", "Glenoid version (3D)", -12.04, "deg", "scapular plane frame"},
      {"inclination", "Glenoid inclination", 8.1, "deg", ""},
      {"removed", "Bone removed by reaming", 2272.2, "mm3", "voxmap before less after"}};
  const std::string sop = bm::WriteMeasurementReport(srPath, src, m);
  EXPECT_FALSE(sop.empty());
  EXPECT_TRUE(DciodvfyErrors(srPath).empty()) << DciodvfyErrors(srPath);
  DcmFileFormat srf;
  ASSERT_TRUE(srf.loadFile(srPath.c_str()).good());
  EXPECT_EQ(Text(*srf.getDataset(), DCM_PatientID), "BM-TEST-7");
  EXPECT_EQ(Text(*srf.getDataset(), DCM_StudyInstanceUID), src.studyUID);
  DSRDocument doc;
  ASSERT_TRUE(doc.read(*srf.getDataset()).good());
  DSRDocumentTree& tree = doc.getTree();
  for (const auto& want : m) {
    tree.gotoRoot();
    ASSERT_GT(
        tree.gotoNamedNode(DSRCodedEntryValue(want.code.c_str(), "99BMSIM", want.name.c_str()),
                           OFTrue, OFTrue),
        0u)
        << want.name;
    const DSRNumericMeasurementValue* v = tree.getCurrentContentItem().getNumericValuePtr();
    ASSERT_NE(v, nullptr);
    EXPECT_NEAR(std::stod(v->getNumericValue().c_str()), want.value, 1e-9) << want.name;
    EXPECT_EQ(std::string(v->getMeasurementUnit().getCodeValue().c_str()), want.unit);
  }
  // Every source image is in the report's image library.
  size_t images = 0;
  tree.gotoRoot();
  do {
    images += tree.getCurrentContentItem().getValueType() == DSRTypes::VT_Image;
  } while (tree.iterate());
  EXPECT_EQ(images, src.images.size());
  // Nothing half-written beside them.
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_NE(e.path().filename().string().rfind('.', 0), 0u) << e.path();
}

TEST(DicomResults, BadInputIsRefusedByName) {
  const fs::path dir = Scratch("bad");
  EXPECT_THROW(bm::ReadDicomSource((dir / "missing").string()), std::runtime_error);
  try {
    bm::ReadDicomSource(dir.string());
    ADD_FAILURE() << "an empty folder gave a source";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("holds no DICOM image series"), std::string::npos)
        << e.what();
  }
  bm::WriteDicomSeries(SmallCT(), (dir / "ct").string());
  const bm::DicomSource src = bm::ReadDicomSource((dir / "ct").string());
  EXPECT_THROW(bm::ReadDicomSource((dir / "ct").string(), "1.2.3.4"), std::runtime_error);
  const Bones b;
  bm::Voxmap other({8, 8, 8}, 0.5, {0, 0, 0});
  EXPECT_THROW(bm::WriteReamingSegmentation((dir / "x.dcm").string(), src, b.before, other),
               std::invalid_argument);
  bm::Voxmap empty({8, 8, 8}, 0.5, {0, 0, 0});
  EXPECT_THROW(bm::WriteReamingSegmentation((dir / "x.dcm").string(), src, empty, empty),
               std::runtime_error);
  EXPECT_THROW(bm::WriteMeasurementReport((dir / "y.dcm").string(), src, {}),
               std::invalid_argument);
  EXPECT_THROW(bm::WriteMeasurementReport((dir / "y.dcm").string(), src,
                                          {{"a-code-far-too-long-for-dicom", "x", 1, "mm", ""}}),
               std::invalid_argument);
  EXPECT_THROW(bm::WriteMeasurementReport((dir / "y.dcm").string(), src,
                                          {{"nan", "Not a number", std::nan(""), "mm", ""}}),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "x.dcm"));
  EXPECT_FALSE(fs::exists(dir / "y.dcm"));
}

TEST(DicomResults, APictureIsASecondaryCaptureInTheCTsStudy) {
  // A report's picture (here a baseline PNG of 400 x 300 pixels) as a Secondary Capture: the
  // CT's patient and study, its own series, the picture's size and pixels in RGB.
  const fs::path dir = Scratch("picture");
  bm::DicomWriteOptions wo;
  wo.patientID = "BM-TEST-SC";
  bm::WriteDicomSeries(SmallCT(), (dir / "ct").string(), wo);
  const bm::DicomSource src = bm::ReadDicomSource((dir / "ct").string());
  const std::string png = std::string(BM_SOURCE_DIR) + "/Testing/Data/Baseline/BMDockCTReader.png";
  bm::DicomPictureInfo info;
  info.description = "the preview, framed";
  info.softwareVersion = "test";
  const std::string path = (dir / "picture.sc.dcm").string();
  const std::string sop = bm::WriteSecondaryCapture(path, src, png, info);
  EXPECT_TRUE(DciodvfyErrors(path).empty()) << DciodvfyErrors(path);
  DcmFileFormat ff;
  ASSERT_TRUE(ff.loadFile(path.c_str()).good());
  DcmDataset& d = *ff.getDataset();
  EXPECT_EQ(Text(d, DCM_SOPClassUID), UID_SecondaryCaptureImageStorage);
  EXPECT_EQ(Text(d, DCM_SOPInstanceUID), sop);
  EXPECT_EQ(Text(d, DCM_PatientID), "BM-TEST-SC");
  EXPECT_EQ(Text(d, DCM_StudyInstanceUID), src.studyUID);
  EXPECT_NE(Text(d, DCM_SeriesInstanceUID), src.seriesUID);
  EXPECT_EQ(Text(d, DCM_PhotometricInterpretation), "RGB");
  EXPECT_NE(Text(d, DCM_DerivationDescription).find(src.seriesUID), std::string::npos);
  Uint16 rows = 0, columns = 0;
  d.findAndGetUint16(DCM_Rows, rows);
  d.findAndGetUint16(DCM_Columns, columns);
  EXPECT_EQ(rows, 300);
  EXPECT_EQ(columns, 400);
  const Uint8* pixels = nullptr;
  unsigned long count = 0;
  ASSERT_TRUE(d.findAndGetUint8Array(DCM_PixelData, pixels, &count).good());
  EXPECT_EQ(count, 400ul * 300ul * 3ul);
  // Not one colour: the picture's pixels, not a blank.
  std::set<int> colours;
  for (unsigned long i = 0; i + 2 < count; i += 3 * 97)
    colours.insert(pixels[i] << 16 | pixels[i + 1] << 8 | pixels[i + 2]);
  EXPECT_GT(colours.size(), 3u);

  // A picture that is not a PNG: refused by name, nothing written.
  const std::string text = (dir / "notes.png").string();
  std::ofstream(text) << "not a picture\n";
  const std::string bad = (dir / "bad.sc.dcm").string();
  try {
    bm::WriteSecondaryCapture(bad, src, text, info);
    ADD_FAILURE() << "a text file was taken for a picture";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("notes.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(bad));
}
