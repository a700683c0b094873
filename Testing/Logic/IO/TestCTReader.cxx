// The reader: compressed transfer syntaxes decode to the same HU, rescale is applied, slices are
// ordered by position whatever the file names, volumes read, progress and cancel work.
#include "bmIOTestUtil.h"

#include "bmCTReader.h"
#include "bmImport.h"

#include <itkImageFileWriter.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>
#include <itkNrrdImageIO.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>

using namespace bmtest;

namespace {

void ExpectSameVoxels(const bm::CTImage& a, const bm::CTImage& b, const std::string& what) {
  ASSERT_EQ(a.Size(), b.Size()) << what;
  const size_t n = a.hu->GetLargestPossibleRegion().GetNumberOfPixels();
  const float* pa = a.hu->GetBufferPointer();
  const float* pb = b.hu->GetBufferPointer();
  size_t diff = 0;
  for (size_t v = 0; v < n; ++v)
    diff += pa[v] != pb[v];
  EXPECT_EQ(diff, 0u) << what;
  for (int a3 = 0; a3 < 3; ++a3) {
    EXPECT_NEAR(a.hu->GetOrigin()[a3], b.hu->GetOrigin()[a3], 1e-6) << what;
    EXPECT_NEAR(a.hu->GetSpacing()[a3], b.hu->GetSpacing()[a3], 1e-9) << what;
  }
}

} // namespace

TEST(CTReader, DicomMatchesThePhantomInHU) {
  ScratchDir d("reader");
  WriteBlock(d / "ct");
  bm::CTImage ct = bm::ReadCT((d / "ct").string());
  bm::CTImage ref = bm::MakePhantomCT("block");
  ASSERT_EQ(ct.Size(), ref.Size());
  EXPECT_EQ(ct.modality, "CT");
  EXPECT_EQ(ct.format, "DICOM");
  // Stored as round(HU) + 1024 with intercept -1024: HU back to within rounding.
  const size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
  double worst = 0;
  for (size_t v = 0; v < n; ++v)
    worst = std::max(
        worst, double(std::abs(ct.hu->GetBufferPointer()[v] -
                               std::max(ref.hu->GetBufferPointer()[v], -1024.0f)))); // stored >= 0
  EXPECT_LE(worst, 0.5 + 1e-3);
  EXPECT_LT(ct.huMin, -900);
  EXPECT_GT(ct.huMax, 1500);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(ct.hu->GetOrigin()[a], ref.hu->GetOrigin()[a], 1e-6);
}

TEST(CTReader, CompressedTransferSyntaxes) {
  ScratchDir d("codecs");
  WriteBlock(d / "plain");
  bm::CTImage plain = bm::ReadCT((d / "plain").string());
  for (const std::string ts : {"rle", "jpeg-lossless", "jpeg-ls", "jpeg2000"}) {
    bm::DicomWriteOptions o;
    o.transferSyntax = ts;
    WriteBlock(d / ts, o);
    bm::CTImage c = bm::ReadCT((d / ts).string());
    EXPECT_NE(c.transferSyntax, plain.transferSyntax) << ts;
    ExpectSameVoxels(c, plain, ts);
  }
}

TEST(CTReader, OrdersSlicesByPositionNotName) {
  ScratchDir d("order");
  WriteBlock(d / "ct");
  bm::CTImage ref = bm::ReadCT((d / "ct").string());
  // Rename the files in reverse order of position.
  auto files = SeriesFiles(d / "ct");
  fs::create_directory(d / "rev");
  for (size_t i = 0; i < files.size(); ++i)
    fs::rename(files[i], d / "rev" / (std::string("S") += std::to_string(1000 - i)));
  bm::CTImage c = bm::ReadCT((d / "rev").string());
  ExpectSameVoxels(c, ref, "reversed names");
}

TEST(CTReader, VolumeFilesReadAsHU) {
  ScratchDir d("volumes");
  bm::CTImage ref = bm::MakePhantomCT("block");
  for (const char* name : {"ct.nrrd", "ct.mha", "ct.nii.gz"}) {
    auto w = itk::ImageFileWriter<bm::HUImage>::New();
    w->SetInput(ref.hu);
    w->SetFileName((d / name).string());
    std::string n = name;
    if (n == "ct.nrrd")
      w->SetImageIO(itk::NrrdImageIO::New());
    else if (n == "ct.mha")
      w->SetImageIO(itk::MetaImageIO::New());
    else
      w->SetImageIO(itk::NiftiImageIO::New());
    w->Update();
    bm::CTImage c = bm::ReadCT((d / name).string());
    ExpectSameVoxels(c, ref, name);
  }
  EXPECT_THROW(bm::ReadCT((d / "ct.png").string()), std::runtime_error);
}

TEST(CTReader, ProgressReachesTheEndAndCancelStops) {
  ScratchDir d("progress");
  WriteBlock(d / "ct");
  double last = -1;
  bool monotone = true;
  std::set<std::string> stages;
  bm::ImportOptions opt;
  opt.resolution = 32;
  bm::ImportVoxmap((d / "ct").string(), opt, bm::Progress([&](double f, const std::string& s) {
                     if (f < last - 1e-12) {
                       monotone = false;
                       ADD_FAILURE()
                           << "progress went back from " << last << " to " << f << " in " << s;
                     }
                     last = f;
                     stages.insert(s);
                     return true;
                   }));
  EXPECT_TRUE(monotone);
  EXPECT_NEAR(last, 1.0, 1e-9);
  EXPECT_TRUE(stages.count("reading DICOM"));
  EXPECT_TRUE(stages.count("resampling into the voxmap"));
  // Cancel in each stage: Cancelled, nothing written.
  for (double at : {0.05, 0.3, 0.6, 0.9}) {
    bm::Progress cancel([at](double f, const std::string&) { return f < at; });
    EXPECT_THROW(bm::ImportToFile((d / "ct").string(), (d / "v.nrrd").string(), opt, cancel),
                 bm::Cancelled)
        << at;
    EXPECT_FALSE(fs::exists(d / "v.nrrd"));
  }
  EXPECT_EQ(d.Entries(), std::vector<std::string>{"ct"});
}

// ---------------------------------------------------------------------------------------------
// DICOM as hospitals export it (Docs/CTImport.md, "DICOM").

namespace {

/// Blank (or remove) the SeriesInstanceUID of every file of a series folder.
void StripSeriesUID(const fs::path& dir, bool remove, const std::string& seriesNumber = "") {
  for (const auto& f : SeriesFiles(dir))
    EditDicom(f, [&](gdcm::DataSet& ds) {
      if (remove)
        ds.Remove(gdcm::Tag(0x0020, 0x000e));
      else
        SetTag(ds, 0x0020, 0x000e, gdcm::VR::UI, "");
      if (!seriesNumber.empty())
        SetTag(ds, 0x0020, 0x0011, gdcm::VR::IS, seriesNumber);
    });
}

} // namespace

TEST(CTReader, SeriesWithEmptyUIDIsGroupedByOtherAttributesAndSaysSo) {
  ScratchDir d("emptyuid");
  WriteBlock(d / "ct");
  bm::CTImage ref = bm::ReadCT((d / "ct").string());
  EXPECT_TRUE(ref.notes.empty());
  StripSeriesUID(d / "ct", false);
  bm::CTImage ct = bm::ReadCT((d / "ct").string());
  ExpectSameVoxels(ct, ref, "empty SeriesInstanceUID");
  EXPECT_EQ(ct.seriesUID.rfind("noUID-", 0), 0u) << ct.seriesUID;
  ASSERT_EQ(ct.notes.size(), 1u);
  EXPECT_NE(ct.notes[0].find("no SeriesInstanceUID"), std::string::npos) << ct.notes[0];
  EXPECT_NE(ct.notes[0].find(ct.seriesUID), std::string::npos) << ct.notes[0];
  // The note reaches the import's summary.
  bm::ImportOptions opt;
  opt.resolution = 32;
  bm::ImportResult r = bm::ImportVoxmap((d / "ct").string(), opt);
  EXPECT_NE(r.Report().find("note:        the series has no SeriesInstanceUID"), std::string::npos)
      << r.Report();
}

TEST(CTReader, SeriesWithoutUIDTagIsGrouped) {
  ScratchDir d("nouid");
  WriteBlock(d / "ct");
  StripSeriesUID(d / "ct", true);
  bm::CTImage ct = bm::ReadCT((d / "ct").string());
  EXPECT_EQ(ct.numFiles, int(SeriesFiles(d / "ct").size()));
  EXPECT_EQ(ct.seriesUID.rfind("noUID-", 0), 0u);
}

TEST(CTReader, SeveralSeriesWithoutUIDAreListedAndChosenById) {
  ScratchDir d("twonouid");
  WriteBlock(d / "a");
  WriteBlock(d / "b");
  StripSeriesUID(d / "a", false, "3");
  StripSeriesUID(d / "b", false, "7");
  fs::create_directory(d / "ct");
  for (const char* s : {"a", "b"})
    for (const auto& f : SeriesFiles(d / s))
      fs::copy(f, d / "ct" / (std::string(s) += f.filename().string()));
  auto list = bm::ListDicomSeries((d / "ct").string());
  ASSERT_EQ(list.size(), 2u);
  const bm::CTImage one = bm::ReadCT((d / "a").string());
  for (const auto& s : list) {
    EXPECT_FALSE(s.hasUID);
    EXPECT_EQ(s.numFiles, one.numFiles);
    EXPECT_EQ(s.cols, one.Size()[0]);
  }
  try {
    bm::ReadCT((d / "ct").string());
    ADD_FAILURE() << "two series were accepted without a choice";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    for (const auto& s : list)
      EXPECT_NE(m.find(s.uid), std::string::npos) << m;
    EXPECT_NE(m.find(std::to_string(one.numFiles) + " slices of " + std::to_string(one.Size()[0]) +
                     " x " + std::to_string(one.Size()[1])),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("series number 7"), std::string::npos) << m;
    EXPECT_NE(m.find("--series"), std::string::npos) << m;
  }
  bm::ReadOptions ro;
  ro.seriesUID = list[1].uid;
  bm::CTImage ct = bm::ReadCT((d / "ct").string(), ro);
  EXPECT_EQ(ct.seriesUID, list[1].uid);
  EXPECT_EQ(ct.numFiles, one.numFiles);
}

TEST(CTReader, SingleDicomFileWithoutExtensionReadsItsSeries) {
  ScratchDir d("single");
  WriteBlock(d / "ct");
  bm::CTImage ref = bm::ReadCT((d / "ct").string());
  fs::create_directory(d / "noext");
  int i = 0;
  for (const auto& f : SeriesFiles(d / "ct"))
    fs::copy(f, d / "noext" / ("IMG" + std::to_string(i++)));
  std::ofstream(d / "noext" / "README") << "not DICOM"; // other files beside it are left alone
  bm::CTImage ct = bm::ReadCT((d / "noext" / "IMG3").string());
  ExpectSameVoxels(ct, ref, "one file of the series");
  ASSERT_FALSE(ct.notes.empty());
  EXPECT_NE(ct.notes.back().find("'IMG3' is one slice of series"), std::string::npos)
      << ct.notes.back();
  // Alone, the file is recognised as DICOM (not "unknown file type"): one slice is no volume.
  fs::create_directory(d / "alone");
  fs::copy(d / "noext" / "IMG3", d / "alone" / "IMG3");
  try {
    bm::ReadCT((d / "alone" / "IMG3").string());
    ADD_FAILURE() << "a single slice was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("single slice"), std::string::npos) << e.what();
  }
}

TEST(CTReader, JPEG2000SeriesConvertedByGdcmconv) {
  if (std::system("gdcmconv --version > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "gdcmconv (libgdcm-tools) is not installed";
  ScratchDir d("j2k");
  WriteBlock(d / "ct");
  bm::CTImage plain = bm::ReadCT((d / "ct").string());
  fs::create_directory(d / "j2k");
  for (const auto& f : SeriesFiles(d / "ct")) {
    const std::string cmd =
        "gdcmconv --j2k '" + f.string() + "' '" + (d / "j2k" / f.filename()).string() + "'";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  bm::CTImage c = bm::ReadCT((d / "j2k").string());
  EXPECT_NE(c.transferSyntax.find("2000"), std::string::npos) << c.transferSyntax;
  ExpectSameVoxels(c, plain, "gdcmconv --j2k");
}
