// The hostile-input corpus (Docs/Reliability.md, "CT import"): small bad files made here, each
// refused by the import with a message naming the problem, no crash, no hang and nothing written.
// Each format's generator also makes a valid control file that reads, so every refusal comes from
// the one thing a case changes.
#include "bmHostileFiles.h"
#include "bmIOTestUtil.h"

#include "bmCTReader.h"
#include "bmImport.h"
#include "bmVoxmapFile.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>

using namespace bmtest;

namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

/// `bytes` compressed as a zlib stream (what MetaImage's CompressedData holds).
std::string Zlib(const std::string& bytes) {
  uLongf size = compressBound(uLong(bytes.size()));
  std::string out(size, '\0');
  compress2(reinterpret_cast<Bytef*>(out.data()), &size,
            reinterpret_cast<const Bytef*>(bytes.data()), uLong(bytes.size()), 9);
  out.resize(size);
  return out;
}

struct Case {
  std::string name;   ///< file or folder name of the hostile input
  std::string needle; ///< what the refusal must say
  std::function<void(const fs::path& input)> make;
  bool allowOutside = false;
};

/// Import `input` expecting a refusal naming `needle`, with nothing written.
void ExpectRefused(const ScratchDir& dir, const Case& c, const fs::path& input) {
  const auto before = dir.Entries();
  const fs::path out = dir / "out.nrrd";
  bm::ImportOptions opt;
  opt.resolution = 16;
  opt.read.allowDataOutsideFolder = c.allowOutside;
  try {
    bm::ImportToFile(input.string(), out.string(), opt);
    ADD_FAILURE() << c.name << ": accepted; expected a refusal naming '" << c.needle << "'";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(c.needle), std::string::npos)
        << c.name << ": message: " << e.what();
  }
  EXPECT_FALSE(fs::exists(out)) << c.name;
  EXPECT_EQ(dir.Entries(), before) << c.name << ": something was written";
}

void RunCorpus(const std::string& tag, const std::vector<Case>& cases) {
  std::cout << "hostile corpus (" << tag << "): " << cases.size() << " cases\n";
  ScratchDir d("hostile-" + tag);
  for (const auto& c : cases) {
    const fs::path folder = d / ("case-" + std::to_string(&c - cases.data()));
    fs::create_directories(folder / "in");
    const fs::path input = folder / "in" / c.name;
    c.make(input);
    ExpectRefused(d, c, input);
  }
}

} // namespace

TEST(HostileInput, ControlFilesRead) {
  ScratchDir d("hostile-control");
  WriteFile(d / "a.nrrd", Nrrd({}));
  WriteFile(d / "a.mha", Mha({}));
  WriteFile(d / "a.nii", Nifti());
  WriteGzip(d / "b.nii.gz", Nifti());
  WriteFile(d / "c.raw", Voxels());
  WriteFile(d / "c.nhdr", Nrrd({{"data file", "c.raw"}}));
  WriteFile(d / "c.mhd", Mha({{"ElementDataFile", "c.raw"}}));
  for (const char* f : {"a.nrrd", "a.mha", "a.nii", "b.nii.gz", "c.nhdr", "c.mhd"}) {
    bm::CTImage ct;
    ASSERT_NO_THROW(ct = bm::ReadCT((d / f).string())) << f;
    EXPECT_EQ(ct.Size(), (std::array<int, 3>{4, 4, 4})) << f;
    EXPECT_EQ(ct.huMin, -1000.0f) << f;
    EXPECT_EQ(ct.huMax, 1000.0f) << f;
  }
}

TEST(HostileInput, NrrdCorpus) {
  auto nrrd = [](std::map<std::string, std::string> f, std::string data = Voxels()) {
    return [f, data](const fs::path& p) { WriteFile(p, Nrrd(f, data)); };
  };
  std::vector<Case> cases = {
      {"fifo.nrrd", "FIFO", [](const fs::path& p) { ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0); }},
      // A link to a kernel file (stat calls /proc/kmsg regular; reading it blocks).
      {"proc.nrrd", "kernel interface file",
       [](const fs::path& p) { fs::create_symlink("/proc/self/status", p); }},
      {"skewed.nrrd", "deg apart, not 90",
       nrrd({{"spacings", "-"},
             {"space", "left-posterior-superior"},
             {"space directions", "(1,0,0) (0.5,0.8660254,0) (0,0,1)"}})},
      {"text.nrrd", "not a NRRD file", [](const fs::path& p) { WriteFile(p, "hello\n"); }},
      {"empty.nrrd", "not a NRRD file", [](const fs::path& p) { WriteFile(p, ""); }},
      {"4d.nrrd", "4-D", nrrd({{"dimension", "4"}, {"sizes", "4 4 4 3"}})},
      {"2d.nrrd", "2-D", nrrd({{"dimension", "2"}, {"sizes", "4 4"}})},
      {"zero-size.nrrd", "size", nrrd({{"sizes", "0 4 4"}})},
      {"neg-size.nrrd", "size", nrrd({{"sizes", "-4 4 4"}})},
      {"word-size.nrrd", "whole numbers", nrrd({{"sizes", "4 x 4"}})},
      {"huge.nrrd", "more than the", nrrd({{"sizes", "100000 100000 100000"}})},
      {"nan-spacing.nrrd", "non-finite voxel spacing", nrrd({{"spacings", "nan 1 1"}})},
      {"inf-spacing.nrrd", "non-finite voxel spacing", nrrd({{"spacings", "1 inf 1"}})},
      {"zero-spacing.nrrd", "voxel spacing of 0", nrrd({{"spacings", "1 1 0"}})},
      {"neg-spacing.nrrd", "voxel spacing of -1", nrrd({{"spacings", "-1 1 1"}})},
      {"denormal-spacing.nrrd", "mm along axis 0: it must be at least 0.0001 mm",
       nrrd({{"spacings", "1e-320 1 1"}})},
      {"vast-spacing.nrrd", "at most 10 000", nrrd({{"spacings", "1e300 1 1"}})},
      {"no-spacing.nrrd", "does not give its voxel spacing", nrrd({{"spacings", "-"}})},
      {"nan-origin.nrrd", "non-finite space origin",
       nrrd({{"spacings", "-"},
             {"space", "left-posterior-superior"},
             {"space directions", "(1,0,0) (0,1,0) (0,0,1)"},
             {"space origin", "(nan,0,0)"}})},
      {"nan-direction.nrrd", "non-finite space direction",
       nrrd({{"spacings", "-"},
             {"space", "left-posterior-superior"},
             {"space directions", "(1,0,0) (0,nan,0) (0,0,1)"}})},
      {"zero-direction.nrrd", "has length 0",
       nrrd({{"spacings", "-"},
             {"space", "left-posterior-superior"},
             {"space directions", "(1,0,0) (0,0,0) (0,0,1)"}})},
      {"bad-type.nrrd", "unsupported NRRD type", nrrd({{"type", "block"}})},
      {"no-type.nrrd", "lacks dimension, sizes or type", nrrd({{"type", "-"}})},
      {"truncated.nrrd", "truncated", nrrd({}, Voxels(20))},
      {"abs-data.nhdr", "absolute path", nrrd({{"data file", "/etc/passwd"}})},
      {"parent-data.nhdr", "'..'", nrrd({{"data file", "../secret.raw"}})},
      {"list-data.nhdr", "list or pattern", nrrd({{"data file", "LIST"}})},
      {"pattern-data.nhdr", "list or pattern", nrrd({{"data file", "slice%03d.raw 1 4 1"}})},
      {"missing-data.nhdr", "does not exist", nrrd({{"data file", "nothing.raw"}})},
      {"folder-data.nhdr", "is a folder",
       [](const fs::path& p) {
         fs::create_directory(p.parent_path() / "sub");
         WriteFile(p, Nrrd({{"data file", "sub"}}));
       }},
      {"devzero.nhdr", "is a device", nrrd({{"data file", "/dev/zero"}}), true},
      {"link-out.nhdr", "outside the header's folder",
       [](const fs::path& p) {
         WriteFile(p.parent_path().parent_path() / "elsewhere.raw", Voxels());
         fs::create_symlink("../elsewhere.raw", p.parent_path() / "link.raw");
         WriteFile(p, Nrrd({{"data file", "link.raw"}}));
       }},
      {"short-data.nhdr", "truncated",
       [](const fs::path& p) {
         WriteFile(p.parent_path() / "short.raw", Voxels(10));
         WriteFile(p, Nrrd({{"data file", "short.raw"}}));
       }},
      {"gzip-cut.nrrd", "",
       [](const fs::path& p) {
         WriteGzip(p.parent_path() / "v.gz", Voxels());
         std::ifstream in(p.parent_path() / "v.gz", std::ios::binary);
         std::string gz((std::istreambuf_iterator<char>(in)), {});
         fs::remove(p.parent_path() / "v.gz");
         WriteFile(p, Nrrd({{"encoding", "gzip"}}, gz.substr(0, gz.size() / 2)));
       }},
      {"many-lines.nrrd", "more than 4096 lines",
       [](const fs::path& p) {
         std::string s = Nrrd({});
         std::string kv;
         for (int i = 0; i < 100000; ++i)
           kv += "key" + std::to_string(i) + ":=v\n";
         WriteFile(p, "NRRD0004\n" + kv + s.substr(9));
       }},
      {"long-line.nrrd", "header is longer than",
       [](const fs::path& p) { WriteFile(p, "NRRD0004\n" + std::string(3 << 20, 'a')); }},
      {"nan-voxels.nrrd", "non-finite voxel value",
       [](const fs::path& p) {
         std::string data;
         for (int i = 0; i < 64; ++i) {
           const float v = i == 5 ? kNaN : -1000.0f + 40.0f * float(i);
           data.append(reinterpret_cast<const char*>(&v), 4);
         }
         WriteFile(p, Nrrd({{"type", "float"}}, data));
       }},
      {"uchar.nrrd", "8-bit",
       [](const fs::path& p) {
         WriteFile(p, Nrrd({{"type", "uchar"}}, std::string(64, '\x80')));
       }},
      {"folder.nrrd", "is empty", [](const fs::path& p) { fs::create_directory(p); }},
  };
  // The gzip case's message depends on where the stream breaks: "truncated" or "corrupt".
  for (auto& c : cases)
    if (c.name == "gzip-cut.nrrd")
      c.needle = "gzip-cut.nrrd";
  RunCorpus("nrrd", cases);
}

TEST(HostileInput, MetaImageCorpus) {
  auto mha = [](std::map<std::string, std::string> f, std::string data = Voxels()) {
    return [f, data](const fs::path& p) { WriteFile(p, Mha(f, data)); };
  };
  std::vector<Case> cases = {
      {"etc-passwd.mha", "absolute path", mha({{"ElementDataFile", "/etc/passwd"}})},
      {"etc-passwd-dotdot.mhd", "'..'",
       mha({{"ElementDataFile", "../../../../../../../../etc/passwd"}})},
      {"is-nrrd.mha", "NRRD file, not a MetaImage",
       [](const fs::path& p) { WriteFile(p, Nrrd({})); }},
      {"4d.mha", "4-D", mha({{"NDims", "4"}, {"DimSize", "4 4 4 2"}})},
      {"no-ndims.mha", "-D image", mha({{"NDims", "three"}})},
      {"zero-dim.mha", "size", mha({{"DimSize", "4 0 4"}})},
      {"huge.mha", "more than the", mha({{"DimSize", "70000 70000 70000"}})},
      {"truncated.mha", "truncated", mha({}, Voxels(30))},
      {"nan-spacing.mha", "non-finite voxel spacing", mha({{"ElementSpacing", "1 nan 1"}})},
      {"zero-spacing.mha", "voxel spacing of 0", mha({{"ElementSpacing", "0 1 1"}})},
      {"nan-offset.mha", "non-finite origin", mha({{"Offset", "0 0 nan"}})},
      {"inf-transform.mha", "non-finite direction",
       mha({{"TransformMatrix", "1 0 0 0 inf 0 0 0 1"}})},
      {"tiny-transform.mha", "direction axis 0 is zero (or nearly",
       mha({{"TransformMatrix", "1e-300 0 0 0 1 0 0 0 1"}})},
      {"zero-transform.mha", "direction axis 1 is zero",
       mha({{"TransformMatrix", "1 0 0 0 0 0 0 0 1"}})},
      {"list.mha", "list or pattern", mha({{"ElementDataFile", "LIST"}})},
      {"channels.mha", "components per voxel", mha({{"ElementNumberOfChannels", "3"}})},
      {"bad-type.mha", "unsupported ElementType", mha({{"ElementType", "MET_STRING"}})},
      {"garbage.mha", "not 'Key = Value'",
       [](const fs::path& p) { WriteFile(p, std::string("\x01\x02\x03 binary\n", 11)); }},
      {"no-datafile.mha", "no ElementDataFile",
       [](const fs::path& p) { WriteFile(p, "NDims = 3\nDimSize = 4 4 4\n"); }},
      {"compressed-cut.mha", "truncated",
       mha({{"CompressedData", "True"}, {"CompressedDataSize", "100000"}}, "xx")},
      {"fifo.mha", "FIFO", [](const fs::path& p) { ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0); }},
      // A zlib stream cut in half with CompressedDataSize saying the cut size: ITK would read
      // half the CT and zeros.
      {"compressed-half.mha", "truncated",
       [](const fs::path& p) {
         const std::string z = Zlib(Voxels(64 * 16)).substr(0, Zlib(Voxels(64 * 16)).size() / 2);
         WriteFile(p, Mha({{"DimSize", "4 4 64"},
                           {"CompressedData", "True"},
                           {"CompressedDataSize", std::to_string(z.size())}},
                          z));
       }},
      {"compressed-garbage.mha", "corrupt",
       mha({{"CompressedData", "True"}, {"CompressedDataSize", "128"}}, std::string(128, 'x'))},
      {"compressed-size-1e2.mha", "is not a whole number of bytes",
       [](const fs::path& p) {
         WriteFile(p, Mha({{"CompressedData", "True"}, {"CompressedDataSize", "1e2"}},
                          Zlib(Voxels()) + std::string(100, '\0')));
       }},
      {"compressed-no-size.mha", "does not give CompressedDataSize",
       [](const fs::path& p) {
         WriteFile(p, Mha({{"CompressedData", "True"}}, Zlib(Voxels())));
       }},
      {"skewed-transform.mha", "deg apart, not 90",
       mha({{"TransformMatrix", "1 0 0 0.5 0.8660254 0 0 0 1"}})},
      {"scaled-transform.mha", "has length 2", mha({{"TransformMatrix", "2 0 0 0 1 0 0 0 1"}})},
  };
  RunCorpus("mha", cases);
}

TEST(HostileInput, NiftiCorpus) {
  auto nii = [](std::function<void(char*)> edit, std::string data = Voxels()) {
    return [edit, data](const fs::path& p) { WriteFile(p, Nifti(edit, data)); };
  };
  std::vector<Case> cases = {
      {"nan-pixdim.nii", "non-finite pixdim", nii([](char* h) { PutFloat(h, 80, kNaN); })},
      {"inf-pixdim.nii", "non-finite pixdim",
       nii([](char* h) { PutFloat(h, 84, std::numeric_limits<float>::infinity()); })},
      {"zero-pixdim.nii", "voxel spacing of 0", nii([](char* h) { PutFloat(h, 88, 0); })},
      {"nan-slope.nii", "non-finite rescale", nii([](char* h) { PutFloat(h, 112, kNaN); })},
      {"inf-inter.nii", "non-finite rescale",
       nii([](char* h) { PutFloat(h, 116, -std::numeric_limits<float>::infinity()); })},
      {"4d.nii", "4-D", nii([](char* h) {
         PutShort(h, 40, 4);
         PutShort(h, 48, 3);
       })},
      {"2d.nii", "2-D", nii([](char* h) { PutShort(h, 40, 2); })},
      {"bad-dim0.nii", "dim[0]", nii([](char* h) { PutShort(h, 40, 9); })},
      {"neg-size.nii", "not positive", nii([](char* h) { PutShort(h, 44, -4); })},
      {"huge.nii", "more than the", nii([](char* h) {
         PutShort(h, 42, 32767);
         PutShort(h, 44, 32767);
         PutShort(h, 46, 32767);
       })},
      {"rgb.nii", "not a scalar type", nii([](char* h) { PutShort(h, 70, 128); })},
      {"nan-qform.nii", "non-finite qform", nii([](char* h) {
         PutShort(h, 252, 1);
         PutFloat(h, 268, kNaN);
       })},
      {"nan-sform.nii", "non-finite sform", nii([](char* h) {
         PutShort(h, 254, 1);
         PutFloat(h, 300, kNaN);
       })},
      {"bad-offset.nii", "vox_offset", nii([](char* h) { PutFloat(h, 108, kNaN); })},
      {"bad-magic.nii", "magic n+1", nii([](char* h) { std::memcpy(h + 344, "xyz", 4); })},
      {"truncated.nii", "truncated", nii({}, Voxels(40))},
      {"short.nii", "too short", [](const fs::path& p) { WriteFile(p, std::string(100, 'x')); }},
      {"not-nifti.nii", "not a NIfTI-1 file",
       [](const fs::path& p) { WriteFile(p, std::string(400, 'x')); }},
      {"truncated.nii.gz", "truncated.nii.gz",
       [](const fs::path& p) { WriteGzip(p, Nifti({}, Voxels(30))); }},
      {"gz-cut.nii.gz", "gz-cut.nii.gz",
       [](const fs::path& p) {
         WriteGzip(p, Nifti());
         fs::resize_file(p, fs::file_size(p) / 2);
       }},
  };
  // qform and sform both set, 40 mm apart: two geometries in one file.
  cases.push_back({"qform-sform-apart.nii", "qform and sform", nii([](char* h) {
                     PutShort(h, 252, 1);
                     PutShort(h, 254, 1);
                     PutFloat(h, 280, 1);
                     PutFloat(h, 300, 1);
                     PutFloat(h, 320, 1);
                     PutFloat(h, 292, 40); // srow_x[3]: the sform's origin 40 mm along x
                   })});
  RunCorpus("nifti", cases);
}

TEST(HostileInput, DicomCorpus) {
  ScratchDir base("hostile-dicom-base");
  WriteBlock(base / "ct");
  const auto files = SeriesFiles(base / "ct");
  const size_t mid = files.size() / 2;
  // A copy of the series with `edit` applied to the data set of file `which` (every file: -1).
  auto series = [&](long which, std::function<void(gdcm::DataSet&)> edit) {
    return [&, which, edit](const fs::path& p) {
      fs::copy(base / "ct", p);
      const auto copies = SeriesFiles(p);
      for (size_t i = 0; i < copies.size(); ++i)
        if (which < 0 || size_t(which) == i)
          EditDicom(copies[i], edit);
    };
  };
  auto tag = [](uint16_t g, uint16_t e, gdcm::VR vr, std::string v) {
    return [=](gdcm::DataSet& ds) { SetTag(ds, g, e, vr, v); };
  };
  std::vector<Case> cases = {
      {"nan-position", "non-finite ImagePositionPatient",
       series(long(mid), tag(0x0020, 0x0032, gdcm::VR::DS, "0\\nan\\3"))},
      {"inf-position", "non-finite ImagePositionPatient",
       series(long(mid), tag(0x0020, 0x0032, gdcm::VR::DS, "inf\\0\\3"))},
      {"nan-orientation", "non-finite ImageOrientationPatient",
       series(-1, tag(0x0020, 0x0037, gdcm::VR::DS, "1\\0\\0\\0\\nan\\0"))},
      {"nan-slope", "RescaleSlope", series(long(mid), tag(0x0028, 0x1053, gdcm::VR::DS, "nan"))},
      {"inf-intercept", "RescaleIntercept",
       series(long(mid), tag(0x0028, 0x1052, gdcm::VR::DS, "-inf"))},
      {"zero-slope", "RescaleSlope (0028,1053) of 0",
       series(-1, tag(0x0028, 0x1053, gdcm::VR::DS, "0"))},
      {"mixed-modality", "unlike the series' first slice",
       series(long(mid), tag(0x0008, 0x0060, gdcm::VR::CS, "MR"))},
      {"no-position", "no ImagePositionPatient",
       series(long(mid), [](gdcm::DataSet& ds) { ds.Remove(gdcm::Tag(0x0020, 0x0032)); })},
      {"tilted-slice", "orientation different",
       series(long(mid), tag(0x0020, 0x0037, gdcm::VR::DS, "1\\0\\0\\0\\0.8\\0.6"))},
      {"other-spacing", "pixel spacing different",
       series(long(mid), tag(0x0028, 0x0030, gdcm::VR::DS, "0.7\\0.7"))},
      {"missing-slice", "inconsistent slice spacing",
       [&](const fs::path& p) {
         fs::copy(base / "ct", p);
         fs::remove(SeriesFiles(p)[mid]);
       }},
      {"same-position", "lie at the same position",
       [&](const fs::path& p) {
         fs::copy(base / "ct", p);
         const auto c = SeriesFiles(p);
         std::string pos;
         EditDicom(c[mid], [&](gdcm::DataSet& ds) {
           const auto& de = ds.GetDataElement(gdcm::Tag(0x0020, 0x0032));
           pos.assign(de.GetByteValue()->GetPointer(), de.GetByteValue()->GetLength());
         });
         EditDicom(c[mid + 1], tag(0x0020, 0x0032, gdcm::VR::DS, pos));
       }},
      {"truncated-slice", "truncated",
       [&](const fs::path& p) {
         fs::copy(base / "ct", p);
         const auto c = SeriesFiles(p)[mid];
         fs::resize_file(c, fs::file_size(c) - 100);
       }},
      {"cut-at-131", "too short",
       [&](const fs::path& p) {
         fs::copy(base / "ct", p);
         fs::resize_file(SeriesFiles(p)[mid], 131);
       }},
      {"cut-at-140", "truncated or corrupt",
       [&](const fs::path& p) {
         fs::copy(base / "ct", p);
         fs::resize_file(SeriesFiles(p)[mid], 140);
       }},
      {"cut-at-150", "truncated or corrupt",
       [&](const fs::path& p) {
         fs::copy(base / "ct", p);
         fs::resize_file(SeriesFiles(p)[mid], 150);
       }},
      {"cut-at-200", "truncated or corrupt",
       [&](const fs::path& p) {
         fs::copy(base / "ct", p);
         fs::resize_file(SeriesFiles(p)[mid], 200);
       }},
      {"cut-at-260", "truncated or corrupt",
       [&](const fs::path& p) {
         fs::copy(base / "ct", p);
         fs::resize_file(SeriesFiles(p)[mid], 260);
       }},
      {"single-file.dcm", "single slice", [&](const fs::path& p) { fs::copy(files[mid], p); }},
      // Orientation: row and column not at right angles (row . column = 0.3), or not unit.
      {"skewed-orientation", "deg apart, not 90",
       series(-1, tag(0x0020, 0x0037, gdcm::VR::DS, "1\\0\\0\\0.3\\0.9539392\\0"))},
      {"long-orientation", "has length 2",
       series(-1, tag(0x0020, 0x0037, gdcm::VR::DS, "2\\0\\0\\0\\2\\0"))},
  };
  // A first, middle or last slice cut where its pixel data begin: a complete data set without an
  // image, which must be named, not left out.
  for (const size_t which : {size_t(0), mid, files.size() - 1})
    cases.push_back({"cut-before-pixels-" + std::to_string(which),
                     files[which].filename().string() + "' in '", [&, which](const fs::path& p) {
                       fs::copy(base / "ct", p);
                       const fs::path f = SeriesFiles(p)[which];
                       fs::resize_file(f, FindBytes(f, std::string("\xe0\x7f\x10\x00", 4)));
                     }});
  // Damage after a sequence of undefined length (real CTs carry them): the element walk goes on
  // through the sequence, so GDCM never sees the damage (it aborts on both).
  auto withSequence = [&](const fs::path& p) {
    fs::copy(base / "ct", p);
    for (const auto& f : SeriesFiles(p))
      EditDicom(f, AddUndefinedLengthSequence);
    return SeriesFiles(p)[mid];
  };
  cases.push_back({"sequence-then-recognition-code", "RecognitionCode", [&](const fs::path& p) {
                     EditDicom(withSequence(p), tag(0x0008, 0x0010, gdcm::VR::LO, "GARBAGE!"));
                   }});
  cases.push_back({"sequence-then-rows-length", "single 2-byte value", [&](const fs::path& p) {
                     const fs::path f = withSequence(p);
                     const size_t at = FindBytes(f, std::string("\x28\x00\x10\x00US\x02\x00", 8));
                     ASSERT_NE(at, std::string::npos);
                     PatchBytes(f, at + 6, std::string("\x04\x00", 2));
                   }});
  cases.push_back({"sequence-then-rows-past-end", "past the file's end", [&](const fs::path& p) {
                     const fs::path f = withSequence(p);
                     const size_t at = FindBytes(f, std::string("\x28\x00\x10\x00US\x02\x00", 8));
                     ASSERT_NE(at, std::string::npos);
                     PatchBytes(f, at + 6, std::string("\xff\xff", 2));
                   }});
  cases.push_back({"sequence-cut-inside", "truncated or corrupt", [&](const fs::path& p) {
                     const fs::path f = withSequence(p);
                     const size_t at = FindBytes(f, std::string("\x08\x00\x06\x00SQ", 6));
                     ASSERT_NE(at, std::string::npos);
                     fs::resize_file(f, at + 40);
                   }});
  RunCorpus("dicom", cases);
}


TEST(HostileInput, InvesaliusCorpus) {
  {
    ScratchDir d("hostile-inv3-control");
    WriteGzip(d / "ok.inv3", Inv3());
    bm::CTImage ct = bm::ReadCT((d / "ok.inv3").string());
    EXPECT_EQ(ct.Size(), (std::array<int, 3>{4, 4, 4}));
    EXPECT_EQ(ct.huMin, -1000.0f);
  }
  auto inv3 = [](std::string content) {
    return [content](const fs::path& p) { WriteGzip(p, content); };
  };
  std::vector<Case> cases = {
      {"text.inv3", "not a readable InVesalius project",
       [](const fs::path& p) { WriteFile(p, "hello, not an archive"); }},
      {"no-plist.inv3", "holds no main.plist", inv3(TarMember("a.txt", "x"))},
      {"neg-shape.inv3", "not a whole number",
       inv3(Inv3(Plist("<integer>-4</integer><integer>4</integer><integer>4</integer>")))},
      {"huge-shape.inv3", "more than the",
       inv3(Inv3(Plist("<integer>900000</integer><integer>900000</integer><integer>900000"
                       "</integer>")))},
      {"word-shape.inv3", "is not a number",
       inv3(Inv3(Plist("<integer>four</integer><integer>4</integer><integer>4</integer>")))},
      {"nan-spacing.inv3", "invalid voxel spacing",
       inv3(Inv3(Plist("<integer>4</integer><integer>4</integer><integer>4</integer>",
                       "<real>nan</real><real>1</real><real>1</real>")))},
      {"long-tag.inv3", "implausibly long",
       inv3(Inv3("<plist><" + std::string(200000, 'a') + ">"))},
      {"short-matrix.inv3", "bytes", inv3(Inv3(Plist(), Voxels(10)))},
      {"cut.inv3", "not a readable InVesalius project",
       [](const fs::path& p) {
         WriteGzip(p, Inv3());
         fs::resize_file(p, fs::file_size(p) / 2);
       }},
  };
  RunCorpus("inv3", cases);
}

TEST(HostileInput, OutputEqualToTheInputIsRefused) {
  ScratchDir d("hostile-out");
  WriteFile(d / "ct.nrrd", Nrrd({}));
  const auto before = fs::file_size(d / "ct.nrrd");
  try {
    bm::ImportToFile((d / "ct.nrrd").string(), (d / "ct.nrrd").string());
    ADD_FAILURE() << "the output overwrote the input";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is the input"), std::string::npos) << e.what();
  }
  EXPECT_EQ(fs::file_size(d / "ct.nrrd"), before);
  WriteBlock(d / "dicom");
  EXPECT_THROW(bm::ImportToFile((d / "dicom").string(), (d / "dicom" / "v.nrrd").string()),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(d / "dicom" / "v.nrrd"));
  // The header's detached data file, named directly or through a link, is the CT too.
  WriteFile(d / "vol.nrrd", Voxels());
  WriteFile(d / "ct.nhdr", Nrrd({{"data file", "vol.nrrd"}}));
  fs::create_symlink(d / "vol.nrrd", d / "link.nrrd");
  for (const char* out : {"vol.nrrd", "link.nrrd"}) {
    try {
      bm::ImportToFile((d / "ct.nhdr").string(), (d / out).string());
      ADD_FAILURE() << "the output " << out << " overwrote the CT's voxels";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("the data file of the input"), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(ReadFile(d / "vol.nrrd"), Voxels()) << out;
  }
  // A link named as the output that leads to the input.
  fs::create_symlink(d / "ct.nrrd", d / "to-ct.nrrd");
  EXPECT_THROW(bm::ImportToFile((d / "ct.nrrd").string(), (d / "to-ct.nrrd").string()),
               std::runtime_error);
  EXPECT_EQ(fs::file_size(d / "ct.nrrd"), before);
  // A name the file system takes but its temporary's does not: refused before the import.
  try {
    bm::ImportToFile((d / "ct.nrrd").string(), (d / (std::string(245, 'a') + ".nrrd")).string());
    ADD_FAILURE() << "a 250-character output name was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds the file system's limit"), std::string::npos)
        << e.what();
  }
  // A slice of a DICOM series given as the input: its folder is the CT.
  EXPECT_THROW(
      bm::ImportToFile(SeriesFiles(d / "dicom")[1].string(), SeriesFiles(d / "dicom")[0].string()),
      std::runtime_error);
}

TEST(HostileInput, ValidGeometryAndCompressionStillRead) {
  ScratchDir d("hostile-valid");
  // A compressed MetaImage as ITK writes it (zlib, CompressedDataSize).
  const std::string z = Zlib(Voxels());
  WriteFile(d / "z.mha",
            Mha({{"CompressedData", "True"}, {"CompressedDataSize", std::to_string(z.size())}}, z));
  // qform and sform both set and agreeing; a rotated (orthonormal) direction.
  WriteFile(d / "qs.nii", Nifti([](char* h) {
              PutShort(h, 252, 1);
              PutShort(h, 254, 1);
              PutFloat(h, 280, 1);
              PutFloat(h, 300, 1);
              PutFloat(h, 320, 1);
            }));
  WriteFile(d / "rot.mha", Mha({{"TransformMatrix", "0.6 0.8 0 -0.8 0.6 0 0 0 1"}}));
  for (const char* f : {"z.mha", "qs.nii", "rot.mha"}) {
    bm::CTImage ct;
    ASSERT_NO_THROW(ct = bm::ReadCT((d / f).string())) << f;
    EXPECT_EQ(ct.huMax, 1000.0f) << f;
  }
  // A DICOM series with sequences of undefined length reads, and a README beside it is skipped
  // and said.
  WriteBlock(d / "ct");
  const bm::CTImage plain = bm::ReadCT((d / "ct").string());
  for (const auto& f : SeriesFiles(d / "ct"))
    EditDicom(f, AddUndefinedLengthSequence);
  WriteFile(d / "ct" / "README", "exported by a PACS\n");
  const bm::CTImage ct = bm::ReadCT((d / "ct").string());
  EXPECT_EQ(ct.Size(), plain.Size());
  ASSERT_FALSE(ct.notes.empty());
  EXPECT_NE(ct.notes.back().find("skipped 1 file that is not DICOM: 'README'"), std::string::npos)
      << ct.notes.back();
}

TEST(HostileInput, SavedVoxmapCorpus) {
  ScratchDir d("hostile-voxmap");
  // Controls: what SaveVoxmap writes, in both formats, and the test's own 2-value MetaImage.
  bm::Voxmap vm({4, 4, 4}, 0.5, {0, 0, 0});
  for (int64_t i = 0; i < vm.StorageSize(); ++i)
    vm.SetFill(i, bm::Voxmap::kFull);
  vm.SetMaterial(vm.Index(1, 2, 3), 0.4f);
  for (const char* name : {"saved.nrrd", "saved.mha"}) {
    bm::SaveVoxmap(vm, (d / name).string());
    bm::Voxmap back({1, 1, 1}, 1.0, {0, 0, 0});
    ASSERT_NO_THROW(back = bm::LoadVoxmap((d / name).string())) << name;
    EXPECT_FLOAT_EQ(back.Material(back.Index(1, 2, 3)), 0.4f) << name;
  }
  WriteFile(d / "control.mha", VoxmapMha(0.5f));
  ASSERT_NO_THROW(bm::LoadVoxmap((d / "control.mha").string()));
  const std::string savedNrrd = [&] {
    std::ifstream in(d / "saved.nrrd", std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"nan-material.mha", "holds material scale nan at voxel (1, 2, 0)"},
      {"inf-material.mha", "holds material scale inf at voxel (1, 2, 0)"},
      {"huge-material.mha", "holds material scale 1e+38 at voxel (1, 2, 0)"},
      {"negative-material.mha", "holds material scale -1 at voxel (1, 2, 0); a material scale "
                                "must be in [0, 10]"},
      {"nrrd-named.mha", "is a NRRD file, not a MetaImage"},
      {"passwd.mha", "absolute path"},
      {"three.mha", "3 components per voxel; at most 2"},
      {"nan-spacing.mha", "non-finite voxel spacing"},
      {"cut.mha", "truncated"},
      {"voxmap.vtk", "a voxmap is .nrrd, .nhdr, .mha or .mhd"},
  };
  WriteFile(d / "nan-material.mha", VoxmapMha(1.0f, 9, kNaN));
  WriteFile(d / "inf-material.mha", VoxmapMha(1.0f, 9, inf));
  WriteFile(d / "huge-material.mha", VoxmapMha(1.0f, 9, 1e38f));
  WriteFile(d / "negative-material.mha", VoxmapMha(1.0f, 9, -1.0f));
  WriteFile(d / "nrrd-named.mha", savedNrrd);
  WriteFile(d / "passwd.mha", VoxmapMha(1.0f, -1, 1.0f, {{"ElementDataFile", "/etc/passwd"}}));
  WriteFile(d / "three.mha", VoxmapMha(1.0f, -1, 1.0f, {{"ElementNumberOfChannels", "3"}}));
  WriteFile(d / "nan-spacing.mha", VoxmapMha(1.0f, -1, 1.0f, {{"ElementSpacing", "nan 1 1"}}));
  WriteFile(d / "cut.mha", VoxmapMha(1.0f).substr(0, 400));
  WriteFile(d / "voxmap.vtk", "# vtk DataFile Version 3.0\n");
  for (const auto& [name, needle] : cases) {
    try {
      bm::LoadVoxmap((d / name).string());
      ADD_FAILURE() << name << ": accepted; expected a refusal naming '" << needle << "'";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
          << name << ": message: " << e.what();
    }
  }
}

// A mutant bmfuzz_dicom found (3000 mutants, seed 1): pixel data whose explicit VR bytes are not a
// VR made GDCM abort on an assertion ("dummy[0] == 0 && dummy[1] == 0"); the element walk now
// refuses it, as it refuses a long VR with non-zero reserved bytes.
TEST(HostileInput, DicomPixelDataWithoutAValidVR) {
  bmtest::ScratchDir d("pixel-vr");
  WriteBlock(d / "ct");
  std::vector<fs::path> slices;
  for (const auto& e : fs::directory_iterator(d / "ct"))
    slices.push_back(e.path());
  std::sort(slices.begin(), slices.end());
  ASSERT_FALSE(slices.empty());
  std::string bytes = bmtest::ReadFile(slices[0]);
  const std::string pixelTag("\xe0\x7f\x10\x00", 4);
  const size_t at = bytes.rfind(pixelTag);
  ASSERT_NE(at, std::string::npos);
  const fs::path file = d / "one.dcm";
  for (const std::string& mangled : {std::string("\x99\x01", 2), std::string("OB\x05\x00", 4)}) {
    std::string b = bytes;
    b.replace(at + 4, mangled.size(), mangled);
    bmtest::WriteFile(file, b);
    try {
      bm::ReadCT(file.string());
      ADD_FAILURE() << "accepted pixel data with a damaged VR";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("pixel data (7fe0,0010)"), std::string::npos)
          << e.what();
    }
  }
}
