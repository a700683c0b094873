// Every bad input to the CT import is refused with a clear message and nothing is written.
#include "bmIOTestUtil.h"

#include "bmCTReader.h"
#include "bmImport.h"

#include <gtest/gtest.h>

#include <fstream>

using namespace bmtest;

namespace {

/// Import `input` into dir/out.nrrd expecting a refusal whose message contains `needle`; checks
/// that the output and no temporary file were written.
void ExpectRefused(const ScratchDir& dir, const fs::path& input, const std::string& needle,
                   bm::ImportOptions opt = {}) {
  opt.resolution = 32;
  const auto before = dir.Entries();
  const fs::path out = dir / "out.nrrd";
  try {
    bm::ImportToFile(input.string(), out.string(), opt);
    ADD_FAILURE() << "import of " << input << " was accepted; expected a refusal naming '" << needle
                  << "'";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << "message: " << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(dir.Entries(), before) << "something was written";
}

} // namespace

TEST(BadInput, EmptyFolder) {
  ScratchDir d("empty");
  fs::create_directory(d / "ct");
  ExpectRefused(d, d / "ct", "is empty");
}

TEST(BadInput, MissingPath) {
  ScratchDir d("missing");
  ExpectRefused(d, d / "nothing-here", "does not exist");
}

TEST(BadInput, TwoSeriesNeedAChoice) {
  ScratchDir d("two");
  bm::DicomWriteOptions a, b;
  a.seriesUID = "1.2.826.0.1.3680043.9.7.1";
  b.seriesUID = "1.2.826.0.1.3680043.9.7.2";
  WriteBlock(d / "a", a);
  WriteBlock(d / "b", b);
  fs::create_directory(d / "ct");
  for (const char* s : {"a", "b"})
    for (const auto& f : SeriesFiles(d / s))
      fs::copy(f, d / "ct" / (std::string(s) += f.filename().string()));
  ExpectRefused(d, d / "ct", "1.2.826.0.1.3680043.9.7.1");
  ExpectRefused(d, d / "ct", "1.2.826.0.1.3680043.9.7.2");
  auto list = bm::ListDicomSeries((d / "ct").string());
  ASSERT_EQ(list.size(), 2u);
  // Picking one by option works.
  bm::ReadOptions ro;
  ro.seriesUID = "1.2.826.0.1.3680043.9.7.2";
  bm::CTImage ct = bm::ReadCT((d / "ct").string(), ro);
  EXPECT_EQ(ct.seriesUID, ro.seriesUID);
  EXPECT_EQ(ct.numFiles, list[1].numFiles);
  // A wrong choice lists what is there.
  bm::ImportOptions opt;
  opt.read.seriesUID = "1.2.3";
  ExpectRefused(d, d / "ct", "1.2.826.0.1.3680043.9.7.1", opt);
}

TEST(BadInput, TruncatedFile) {
  ScratchDir d("trunc");
  WriteBlock(d / "ct");
  auto files = SeriesFiles(d / "ct");
  fs::path victim = files[files.size() / 2];
  fs::resize_file(victim, fs::file_size(victim) / 2);
  ExpectRefused(d, d / "ct", victim.filename().string());
}

TEST(BadInput, CorruptFile) {
  ScratchDir d("corrupt");
  WriteBlock(d / "ct");
  auto files = SeriesFiles(d / "ct");
  fs::path victim = files[3];
  {
    std::fstream f(victim, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(128); // clobber the DICM magic and the meta header
    std::string junk(600, '\x5a');
    f.write(junk.data(), std::streamsize(junk.size()));
  }
  ExpectRefused(d, d / "ct", victim.filename().string());
}

TEST(BadInput, NonCTModality) {
  ScratchDir d("mr");
  bm::DicomWriteOptions mr;
  mr.modality = "MR";
  WriteBlock(d / "ct", mr);
  ExpectRefused(d, d / "ct", "modality 'MR'");
}

TEST(BadInput, MissingPixelSpacing) {
  ScratchDir d("nospacing");
  WriteBlock(d / "ct");
  for (const auto& f : SeriesFiles(d / "ct"))
    EditDicom(f, [](gdcm::DataSet& ds) { ds.Remove(gdcm::Tag(0x0028, 0x0030)); });
  ExpectRefused(d, d / "ct", "PixelSpacing");
}

TEST(BadInput, ZeroPixelSpacing) {
  ScratchDir d("zerospacing");
  WriteBlock(d / "ct");
  for (const auto& f : SeriesFiles(d / "ct"))
    EditDicom(f, [](gdcm::DataSet& ds) { SetTag(ds, 0x0028, 0x0030, gdcm::VR::DS, "0\\0"); });
  ExpectRefused(d, d / "ct", "zero");
}

TEST(BadInput, VolumeWithoutSpacing) {
  ScratchDir d("nrrdnospacing");
  {
    std::ofstream f(d / "ct.nrrd", std::ios::binary);
    f << "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nendian: little\nencoding: raw\n\n";
    std::string zeros(4 * 4 * 4 * 2, '\0');
    f.write(zeros.data(), std::streamsize(zeros.size()));
  }
  ExpectRefused(d, d / "ct.nrrd", "spacing");
}

TEST(BadInput, InconsistentSliceSpacing) {
  ScratchDir d("gap");
  WriteBlock(d / "ct");
  auto files = SeriesFiles(d / "ct");
  fs::remove(files[files.size() / 2]); // a missing slice
  ExpectRefused(d, d / "ct", "inconsistent slice spacing");
}

TEST(BadInput, TooLargeForTheMemoryAllowed) {
  ScratchDir d("big");
  WriteBlock(d / "ct");
  bm::ImportOptions opt;
  opt.read.maxMemoryBytes = 10000;
  ExpectRefused(d, d / "ct", "more than the", opt);
  // Checked before allocating: a header claiming 4000^3 voxels (256 GB as float) over a tiny file
  // is refused at once, under the default limit.
  {
    std::ofstream f(d / "huge.nhdr");
    f << "NRRD0004\ntype: short\ndimension: 3\nsizes: 4000 4000 4000\nspacings: 0.5 0.5 0.5\n"
         "endian: little\nencoding: raw\ndata file: huge.raw\n\n";
    std::ofstream(d / "huge.raw") << "x";
  }
  ExpectRefused(d, d / "huge.nhdr", "more than the");
  // A CT that fits but whose segmentation does not (22 bytes per voxel in all): refused from its
  // header with the import's need, not after it was read.
  {
    std::ofstream f(d / "mid.nhdr");
    f << "NRRD0004\ntype: short\ndimension: 3\nsizes: 100 100 100\nspacings: 0.5 0.5 0.5\n"
         "endian: little\nencoding: raw\ndata file: mid.raw\n\n";
    std::ofstream(d / "mid.raw", std::ios::binary) << std::string(2000000, '\0');
  }
  bm::ImportOptions mid;
  mid.read.maxMemoryBytes = 10 << 20; // the CT's 4 MB fit, the import's 22 MB do not
  ExpectRefused(d, d / "mid.nhdr", "with the import's working memory (22 bytes per voxel)", mid);
}

TEST(BadInput, SeedOutsideTheImage) {
  ScratchDir d("seed");
  WriteBlock(d / "ct");
  bm::ImportOptions opt;
  opt.segmentation.seedMm = std::array<double, 3>{100, 0, 0};
  ExpectRefused(d, d / "ct", "outside the image", opt);
}

TEST(BadInput, SeedNotOnBone) {
  ScratchDir d("seedair");
  WriteBlock(d / "ct");
  bm::ImportOptions opt;
  opt.segmentation.seedMm = std::array<double, 3>{0, 0, 4}; // in the air above the block
  ExpectRefused(d, d / "ct", "not on bone", opt);
}

TEST(BadInput, ThresholdFindsNoBone) {
  ScratchDir d("nobone");
  WriteBlock(d / "ct");
  bm::ImportOptions opt;
  opt.segmentation.thresholdHU = 5000;
  ExpectRefused(d, d / "ct", "no bone found", opt);
}

TEST(BadInput, RoiOutsideTheImage) {
  ScratchDir d("roi");
  WriteBlock(d / "ct");
  bm::ImportOptions opt;
  opt.roiMm = bm::Box3{{100, 100, 100}, {110, 110, 110}};
  ExpectRefused(d, d / "ct", "outside the CT", opt);
}

TEST(BadInput, BadOutputPathWritesNothing) {
  ScratchDir d("out");
  WriteBlock(d / "ct");
  EXPECT_THROW(bm::ImportToFile((d / "ct").string(), (d / "v.png").string()), std::runtime_error);
  EXPECT_THROW(bm::ImportToFile((d / "ct").string(), (d / "no" / "v.nrrd").string()),
               std::runtime_error);
  EXPECT_EQ(d.Entries(), std::vector<std::string>{"ct"});
}
