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

#include <algorithm>
#include <array>
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

// ---------------------------------------------------------------------------------------------
// Gantry tilt and sheared slice positions (Docs/CTImport.md, "Tilted slices"): the slices' planes
// are not stacked along their normal. A sphere of bone at a known centre is scanned on such a grid
// and written as DICOM; read back, its centre and size must be where they are (within 0.5 mm).

namespace {

constexpr double kSphereRadiusMm = 7.0;
const std::array<double, 3> kSphereCentre{3.0, -4.0, 20.0};

/// A sphere of bone (1500 HU in air, partial volume by 4^3 sub-samples) on the grid whose voxel
/// (i, j, k) lies at origin + i * 0.5 mm * row + j * 0.5 mm * column + k * step, its centre at
/// voxel (24, 24, 20) of 48 x 48 x 40.
bm::CTImage SphereOnGrid(const std::array<double, 3>& row, const std::array<double, 3>& column,
                         const std::array<double, 3>& step) {
  const double sp = 0.5;
  const size_t n[3] = {48, 48, 40};
  double stepLen = 0;
  for (double v : step)
    stepLen += v * v;
  stepLen = std::sqrt(stepLen);
  bm::CTImage ct;
  ct.hu = bm::HUImage::New();
  bm::HUImage::RegionType region;
  region.SetSize({{n[0], n[1], n[2]}});
  ct.hu->SetRegions(region);
  bm::HUImage::SpacingType spacing;
  spacing[0] = spacing[1] = sp;
  spacing[2] = stepLen;
  ct.hu->SetSpacing(spacing);
  bm::HUImage::DirectionType d;
  bm::HUImage::PointType origin;
  for (int a = 0; a < 3; ++a) {
    d[a][0] = row[a];
    d[a][1] = column[a];
    d[a][2] = step[a] / stepLen;
    origin[a] = kSphereCentre[a] - 24 * sp * row[a] - 24 * sp * column[a] - 20 * step[a];
  }
  ct.hu->SetDirection(d);
  ct.hu->SetOrigin(origin);
  ct.hu->Allocate();
  float* v = ct.hu->GetBufferPointer();
  const int ss = 4;
  for (size_t k = 0; k < n[2]; ++k)
    for (size_t j = 0; j < n[1]; ++j)
      for (size_t i = 0; i < n[0]; ++i) {
        int inside = 0;
        for (int c = 0; c < ss; ++c)
          for (int b = 0; b < ss; ++b)
            for (int a = 0; a < ss; ++a) {
              const double fi = double(i) + (a + 0.5) / ss - 0.5;
              const double fj = double(j) + (b + 0.5) / ss - 0.5;
              const double fk = double(k) + (c + 0.5) / ss - 0.5;
              double r2 = 0;
              for (int e = 0; e < 3; ++e) {
                const double p = origin[e] + fi * sp * row[e] + fj * sp * column[e] + fk * step[e];
                r2 += (p - kSphereCentre[e]) * (p - kSphereCentre[e]);
              }
              inside += r2 <= kSphereRadiusMm * kSphereRadiusMm;
            }
        v[i + n[0] * (j + n[1] * k)] = float(-1000.0 + 2500.0 * inside / (ss * ss * ss));
      }
  return ct;
}

/// Bone fraction-weighted centre (mm) and volume (mm^3) of a CT of the sphere.
void SphereOf(const bm::CTImage& ct, std::array<double, 3>& centre, double& volume) {
  const auto size = ct.hu->GetLargestPossibleRegion().GetSize();
  const auto sp = ct.hu->GetSpacing();
  double sum = 0, c[3] = {0, 0, 0};
  itk::Index<3> idx;
  itk::Point<double, 3> p;
  for (size_t k = 0; k < size[2]; ++k)
    for (size_t j = 0; j < size[1]; ++j)
      for (size_t i = 0; i < size[0]; ++i) {
        idx = {{long(i), long(j), long(k)}};
        const double f = std::clamp((ct.hu->GetPixel(idx) + 1000.0) / 2500.0, 0.0, 1.0);
        if (f <= 0.01)
          continue;
        ct.hu->TransformIndexToPhysicalPoint(idx, p);
        sum += f;
        for (int a = 0; a < 3; ++a)
          c[a] += f * p[a];
      }
  for (int a = 0; a < 3; ++a)
    centre[a] = c[a] / sum;
  volume = sum * sp[0] * sp[1] * sp[2];
}

double DistanceMm(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

struct TiltCase {
  const char* name;
  std::array<double, 3> row, column, step;
  double planeGapMm; // distance between the slice planes
};

std::vector<TiltCase> TiltCases() {
  const auto tilt = [](const char* name, double deg) {
    const double t = deg * M_PI / 180;
    // Gantry tilt about the row (x) axis; the table moves along z in 1 mm steps.
    return TiltCase{name, {1, 0, 0}, {0, std::cos(t), std::sin(t)}, {0, 0, 1.0}, std::cos(t)};
  };
  return {tilt("5 deg gantry tilt", 5), tilt("20 deg gantry tilt", 20),
          tilt("-15 deg gantry tilt", -15),
          // Positions sheared in the slice plane: 0.3 mm along the rows per 1 mm slice.
          TiltCase{"sheared positions", {1, 0, 0}, {0, 1, 0}, {0.3, 0, 1.0}, 1.0},
          // An oblique series whose positions also move within the plane.
          TiltCase{"oblique and sheared",
                   {std::cos(0.3), std::sin(0.3), 0},
                   {-std::sin(0.3), std::cos(0.3), 0},
                   {0.2, -0.25, 1.25},
                   1.25}};
}

} // namespace

TEST(CTReader, GantryTiltAndShearedPositionsKeepTheBoneInPlace) {
  ScratchDir d("tilt");
  const std::vector<TiltCase> cases = TiltCases();
  for (size_t ci = 0; ci < cases.size(); ++ci) {
    const TiltCase& c = cases[ci];
    const bm::CTImage truth = SphereOnGrid(c.row, c.column, c.step);
    const fs::path dir = d / ("ct-" + std::to_string(ci));
    fs::remove_all(dir);
    bm::WriteDicomSeries(truth, dir.string());
    const bm::CTImage ct = bm::ReadCT(dir.string());
    // An orthogonal grid along the slice normal, the planes as far apart as they are.
    const auto D = ct.hu->GetDirection();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        double dot = 0;
        for (int e = 0; e < 3; ++e)
          dot += D[e][a] * D[e][b];
        EXPECT_NEAR(dot, a == b ? 1.0 : 0.0, 1e-9) << c.name;
      }
    EXPECT_NEAR(ct.hu->GetSpacing()[2], c.planeGapMm, 1e-3) << c.name;
    ASSERT_FALSE(ct.notes.empty()) << c.name;
    EXPECT_NE(ct.notes.front().find("deg off the slice normal"), std::string::npos)
        << ct.notes.front();
    std::array<double, 3> centre;
    double volume = 0;
    SphereOf(ct, centre, volume);
    EXPECT_LT(DistanceMm(centre, kSphereCentre), 0.5)
        << c.name << ": centre (" << centre[0] << ", " << centre[1] << ", " << centre[2] << ")";
    const double sphere = 4.0 / 3.0 * M_PI * std::pow(kSphereRadiusMm, 3);
    EXPECT_NEAR(volume, sphere, 0.03 * sphere) << c.name;
    // The bone's extent along each world axis: the sphere's, within 0.5 mm.
    bm::ImportOptions opt;
    opt.resolution = 64;
    const bm::ImportResult r = bm::ImportVoxmap(dir.string(), opt);
    double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9}, sum = 0, mc[3] = {0, 0, 0};
    const auto dims = r.voxmap.Dims();
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          const double f = r.voxmap.Fraction(r.voxmap.Index(i, j, k));
          if (f <= 0)
            continue;
          const auto p = r.voxmap.GridToWorld({double(i), double(j), double(k)});
          sum += f;
          for (int a = 0; a < 3; ++a) {
            mc[a] += f * p[a];
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
          }
        }
    ASSERT_GT(sum, 0) << c.name;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(mc[a] / sum, kSphereCentre[a], 0.5) << c.name << " voxmap centre, axis " << a;
      EXPECT_NEAR(0.5 * (lo[a] + hi[a]), kSphereCentre[a], 0.5) << c.name << " extent, axis " << a;
    }
  }
}

TEST(CTReader, SlicePositionsOffTheirLineAreNamed) {
  ScratchDir d("offline");
  const bm::CTImage truth = SphereOnGrid({1, 0, 0}, {0, 1, 0}, {0, 0, 1.0});
  bm::WriteDicomSeries(truth, (d / "ct").string());
  const auto files = SeriesFiles(d / "ct");
  // One slice moved 2 mm within its plane: not a tilt (the others do not move), a damaged position.
  EditDicom(files[17], [&](gdcm::DataSet& ds) {
    itk::Index<3> idx{{0, 0, 17}};
    itk::Point<double, 3> p;
    truth.hu->TransformIndexToPhysicalPoint(idx, p);
    SetTag(ds, 0x0020, 0x0032, gdcm::VR::DS,
           std::to_string(p[0] + 2.0) + "\\" + std::to_string(p[1]) + "\\" + std::to_string(p[2]));
  });
  try {
    bm::ReadCT((d / "ct").string());
    ADD_FAILURE() << "a slice off the others' line was accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(files[17].filename().string()), std::string::npos) << m;
    EXPECT_NE(m.find("off the line"), std::string::npos) << m;
  }
}
