// Intensities that say what they are (Docs/CTImport.md, "Intensities"): HU is recognised, an 8-bit
// windowed volume is refused with the reason and both overrides, and each override imports it
// with the mapping recorded in the summary and the voxmap file.
#include "bmIOTestUtil.h"

#include "bmCTReader.h"
#include "bmCTVoxmap.h"
#include "bmImport.h"
#include "bmIntensityMapping.h"

#include <itkImageFileWriter.h>
#include <itkNrrdImageIO.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

using namespace bmtest;

namespace {

// The window the 8-bit volume is written with: HU -500 -> 0, HU 1500 -> 255.
constexpr double kLow = -500, kHigh = 1500;
constexpr double kSlope = (kHigh - kLow) / 255.0; // HU per 8-bit step

/// The block phantom as an 8-bit windowed NRRD (what a viewer exports as "display values").
fs::path WriteWindowed8Bit(const ScratchDir& d) {
  bm::CTImage ct = bm::MakePhantomCT("block");
  using U8 = itk::Image<unsigned char, 3>;
  auto img = U8::New();
  img->SetRegions(ct.hu->GetLargestPossibleRegion());
  img->SetSpacing(ct.hu->GetSpacing());
  img->SetOrigin(ct.hu->GetOrigin());
  img->SetDirection(ct.hu->GetDirection());
  img->Allocate();
  const size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
  for (size_t i = 0; i < n; ++i) {
    const double v = (double(ct.hu->GetBufferPointer()[i]) - kLow) / kSlope;
    img->GetBufferPointer()[i] = (unsigned char)std::lround(std::clamp(v, 0.0, 255.0));
  }
  const fs::path file = d / "windowed.nrrd";
  auto w = itk::ImageFileWriter<U8>::New();
  w->SetInput(img);
  w->SetImageIO(itk::NrrdImageIO::New());
  w->SetFileName(file.string());
  w->Update();
  return file;
}

std::string ReadText(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

} // namespace

TEST(IntensityMapping, DicomCTIsHUAndCalibrated) {
  ScratchDir d("hu");
  WriteBlock(d / "ct");
  bm::CTImage ct = bm::ReadCT((d / "ct").string());
  EXPECT_EQ(ct.intensity.kind, bm::IntensityKind::HU);
  EXPECT_TRUE(ct.intensity.materialCalibrated);
  EXPECT_NE(ct.intensity.basis.find("DICOM CT"), std::string::npos) << ct.intensity.basis;
}

TEST(IntensityMapping, Windowed8BitVolumeIsRefusedWithTheReasonAndTheOverrides) {
  ScratchDir d("u8");
  const fs::path file = WriteWindowed8Bit(d);
  try {
    bm::ReadCT(file.string());
    ADD_FAILURE() << "an 8-bit windowed volume was taken as HU";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("8-bit"), std::string::npos) << m;
    EXPECT_NE(m.find("not Hounsfield units"), std::string::npos) << m;
    EXPECT_NE(m.find("--raw-threshold"), std::string::npos) << m;
    EXPECT_NE(m.find("--hu-mapping"), std::string::npos) << m;
  }
  // The same values stored wider (16-bit, no rescale) are still not HU.
  std::vector<std::string> warnings;
  bm::IntensityEvidence wide;
  wide.file = "x.nrrd";
  wide.format = "NRRD";
  wide.storedBits = 16;
  wide.minValue = 0;
  wide.maxValue = 255;
  EXPECT_THROW(bm::DecideIntensity(wide, {}, warnings), std::runtime_error);
  // A CT in HU (air near -1000) is HU.
  wide.minValue = -1024;
  wide.maxValue = 2000;
  EXPECT_EQ(bm::DecideIntensity(wide, {}, warnings).kind, bm::IntensityKind::HU);
  EXPECT_TRUE(warnings.empty());
}

TEST(IntensityMapping, RawThresholdImportsWithUniformUncalibratedMaterial) {
  ScratchDir d("raw");
  const fs::path file = WriteWindowed8Bit(d);
  bm::ImportOptions opt;
  opt.resolution = 32;
  opt.read.intensity.rawThreshold = (200 - kLow) / kSlope; // 200 HU in the file's units
  bm::ImportResult r = bm::ImportToFile(file.string(), (d / "raw.nrrd").string(), opt);
  EXPECT_EQ(r.intensity.kind, bm::IntensityKind::Raw);
  EXPECT_FALSE(r.intensity.materialCalibrated);
  EXPECT_GT(r.voxmap.CountBone(), 0);
  for (int64_t i = 0; i < r.voxmap.StorageSize(); ++i)
    ASSERT_EQ(r.voxmap.Material(i), 1.0f) << "voxel " << i;
  EXPECT_NE(r.Report().find("raw values, bone threshold"), std::string::npos) << r.Report();
  EXPECT_NE(r.Report().find("not calibrated"), std::string::npos) << r.Report();
  const std::string header = ReadText(d / "raw.nrrd").substr(0, 2000);
  EXPECT_NE(header.find("bm_intensity_mapping:=raw"), std::string::npos) << header;
  EXPECT_NE(header.find("bm_material_calibrated:=false"), std::string::npos) << header;
}

TEST(IntensityMapping, GivenMappingImportsLikeTheHUVolume) {
  ScratchDir d("mapped");
  const fs::path file = WriteWindowed8Bit(d);
  bm::ImportOptions opt;
  opt.resolution = 32;
  opt.read.intensity.huMapping = std::array<double, 2>{kSlope, kLow};
  bm::ImportResult mapped = bm::ImportToFile(file.string(), (d / "m.nrrd").string(), opt);
  EXPECT_EQ(mapped.intensity.kind, bm::IntensityKind::GivenMapping);
  EXPECT_TRUE(mapped.intensity.materialCalibrated);
  EXPECT_NEAR(mapped.huMin, kLow, 1e-3);
  EXPECT_NEAR(mapped.huMax, kHigh, 1e-3);
  bm::ImportOptions huOpt;
  huOpt.resolution = 32;
  bm::ImportResult hu = bm::ImportVoxmap(bm::MakePhantomCT("block"), huOpt);
  EXPECT_NEAR(mapped.segmentedVolumeMm3, hu.segmentedVolumeMm3, 0.03 * hu.segmentedVolumeMm3);
  const std::string header = ReadText(d / "m.nrrd").substr(0, 2000);
  EXPECT_NE(header.find("bm_intensity_mapping:=given-mapping"), std::string::npos) << header;
  EXPECT_NE(header.find("bm_material_calibrated:=true"), std::string::npos) << header;
}

// An image handed over in memory (the plugin's input from a ParaView reader) is read as a file
// is: the same refusal of windowed 8-bit values, the same overrides, non-finite values refused.
TEST(IntensityMapping, InMemoryVolumeGoesThroughTheSameDecision) {
  bm::CTImage block = bm::MakePhantomCT("block");
  const size_t n = block.hu->GetLargestPossibleRegion().GetNumberOfPixels();
  std::vector<float> windowed(n);
  for (size_t i = 0; i < n; ++i)
    windowed[i] = float(std::lround(
        std::clamp((double(block.hu->GetBufferPointer()[i]) - kLow) / kSlope, 0.0, 255.0)));
  bm::CTVolumeView view;
  view.values = windowed.data();
  for (unsigned a = 0; a < 3; ++a) {
    view.dims[a] = int(block.hu->GetLargestPossibleRegion().GetSize()[a]);
    view.spacing[a] = block.hu->GetSpacing()[a];
    view.origin[a] = block.hu->GetOrigin()[a];
  }
  view.source = "the input image";
  view.storedBits = 8;
  view.storedInteger = true;
  try {
    bm::MakeCTVoxmapFromVolume(view, nlohmann::json::object(), 32);
    ADD_FAILURE() << "an 8-bit windowed image in memory was taken as HU";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("the input image"), std::string::npos) << m;
    EXPECT_NE(m.find("not Hounsfield units"), std::string::npos) << m;
  }
  std::string report;
  bm::Voxmap raw = bm::MakeCTVoxmapFromVolume(
      view, {{"rawThreshold", (200 - kLow) / kSlope}}, 32, {}, &report);
  EXPECT_GT(raw.CountBone(), 0);
  EXPECT_NE(report.find("raw values, bone threshold"), std::string::npos) << report;
  bm::Voxmap mapped = bm::MakeCTVoxmapFromVolume(
      view, {{"huMapping", {kSlope, kLow}}, {"threshold", 200}}, 32, {}, &report);
  EXPECT_NE(report.find("given mapping"), std::string::npos) << report;
  bm::ImportOptions huOpt;
  huOpt.resolution = 32;
  bm::ImportResult hu = bm::ImportVoxmap(bm::MakePhantomCT("block"), huOpt);
  EXPECT_NEAR(mapped.BoneVolume(), hu.voxmap.BoneVolume(), 0.03 * hu.voxmap.BoneVolume());
  windowed[n / 2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(bm::MakeCTVoxmapFromVolume(view, {{"rawThreshold", 100}}, 32), std::runtime_error);
}

TEST(IntensityMapping, InvalidOverridesAreRefused) {
  std::vector<std::string> warnings;
  bm::IntensityEvidence e;
  e.minValue = -1000;
  e.maxValue = 2000;
  bm::IntensityOptions both;
  both.rawThreshold = 100;
  both.huMapping = std::array<double, 2>{1, 0};
  EXPECT_THROW(bm::DecideIntensity(e, both, warnings), std::runtime_error);
  bm::IntensityOptions zero;
  zero.huMapping = std::array<double, 2>{0, 0};
  EXPECT_THROW(bm::DecideIntensity(e, zero, warnings), std::runtime_error);
  bm::IntensityOptions nan;
  nan.rawThreshold = std::nan("");
  EXPECT_THROW(bm::DecideIntensity(e, nan, warnings), std::runtime_error);
}

TEST(IntensityMapping, SceneKeysSayHowToReadTheValues) {
  bm::ImportOptions raw = bm::ImportOptionsFromJson(nlohmann::json{{"rawThreshold", 89}});
  ASSERT_TRUE(raw.read.intensity.rawThreshold);
  EXPECT_EQ(*raw.read.intensity.rawThreshold, 89);
  bm::ImportOptions mapped = bm::ImportOptionsFromJson(
      nlohmann::json{{"huMapping", {2, -1000}}, {"allowOutsideData", true}});
  ASSERT_TRUE(mapped.read.intensity.huMapping);
  EXPECT_EQ((*mapped.read.intensity.huMapping)[0], 2);
  EXPECT_EQ((*mapped.read.intensity.huMapping)[1], -1000);
  EXPECT_TRUE(mapped.read.allowDataOutsideFolder);
  EXPECT_THROW(bm::ImportOptionsFromJson(nlohmann::json{{"threshold", 200}, {"rawThreshold", 89}}),
               std::runtime_error);
  EXPECT_THROW(bm::ImportOptionsFromJson(nlohmann::json{{"huMapping", {1}}}), std::runtime_error);
}
