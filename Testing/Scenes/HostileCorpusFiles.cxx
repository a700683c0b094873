// HostileCorpusFiles.cxx - the corpus's file cases (bmHostileCorpus.h): every reader of user
// files given damaged inputs made here (no binary blobs).
#include "bmHostileCorpus.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace bmcorpus {
namespace {

using namespace bmtest;

// ---------------------------------------------------------------------------------------------
// Files: every reader of user files.

/// Replace the value of top-level element (group, element) of an explicit-VR little-endian
/// DICOM file (short VR form), padding it to even length.
void SetDicomValue(const fs::path& file, uint16_t group, uint16_t element, std::string value) {
  std::string d = ReadFile(file);
  const char tag[4] = {char(group & 0xff), char(group >> 8), char(element & 0xff),
                       char(element >> 8)};
  const size_t at = d.find(std::string(tag, 4), 132);
  if (at == std::string::npos)
    throw std::runtime_error("SetDicomValue: no element in " + file.string());
  if (value.size() % 2)
    value += ' ';
  const uint16_t oldLength = uint16_t(uint8_t(d[at + 6]) | (uint8_t(d[at + 7]) << 8));
  const uint16_t newLength = uint16_t(value.size());
  d[at + 6] = char(newLength & 0xff);
  d[at + 7] = char(newLength >> 8);
  d.replace(at + 8, oldLength, value);
  WriteFile(file, d);
}

std::vector<fs::path> Slices(const fs::path& dir) {
  std::vector<fs::path> v;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".dcm")
      v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

/// Import of `file` (made by `make` in the input folder).
void Import(const std::string& name, const std::vector<std::string>& needles,
            std::function<void(const fs::path&)> make, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"import", "{in}/" + name, "--out", "{out}/v.nrrd",
                                   "-q",     "--resolution", "16"};
  args.insert(args.end(), extra.begin(), extra.end());
  Add("import " + name, args, needles, std::move(make));
}

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

void VolumeCases() {
  auto nrrd = [](const std::string& name, const std::string& needle,
                 std::map<std::string, std::string> f, std::string data = Voxels()) {
    Import(name, {name, needle}, Writes(name, Nrrd(f, data)));
  };
  nrrd("4d.nrrd", "4-D", {{"dimension", "4"}, {"sizes", "4 4 4 3"}});
  nrrd("2d.nrrd", "2-D", {{"dimension", "2"}, {"sizes", "4 4"}});
  nrrd("1d.nrrd", "1-D", {{"dimension", "1"}, {"sizes", "64"}});
  nrrd("zero-size.nrrd", "size", {{"sizes", "0 4 4"}});
  nrrd("neg-size.nrrd", "size", {{"sizes", "-4 4 4"}});
  nrrd("word-size.nrrd", "whole numbers", {{"sizes", "4 x 4"}});
  nrrd("frac-size.nrrd", "is not a whole number", {{"sizes", "4 4.5 4"}});
  nrrd("few-sizes.nrrd", "size", {{"sizes", "4 4"}});
  nrrd("huge.nrrd", "more than the", {{"sizes", "100000 100000 100000"}});
  nrrd("huge-int.nrrd", "size", {{"sizes", "99999999999999999999 4 4"}});
  for (const std::string v : {"nan", "inf", "-inf"})
    nrrd(v + "-spacing.nrrd", "non-finite voxel spacing", {{"spacings", "1 " + v + " 1"}});
  nrrd("zero-spacing.nrrd", "voxel spacing of 0", {{"spacings", "1 1 0"}});
  nrrd("neg-spacing.nrrd", "voxel spacing of -1", {{"spacings", "-1 1 1"}});
  nrrd("denormal-spacing.nrrd", "at least 0.0001 mm", {{"spacings", "1e-320 1 1"}});
  nrrd("vast-spacing.nrrd", "at most 10 000", {{"spacings", "1e300 1 1"}});
  nrrd("no-spacing.nrrd", "voxel spacing", {{"spacings", "-"}});
  const std::map<std::string, std::string> lps = {{"spacings", "-"},
                                                  {"space", "left-posterior-superior"},
                                                  {"space directions", "(1,0,0) (0,1,0) (0,0,1)"}};
  for (const std::string v : {"nan", "inf"}) {
    auto f = lps;
    f["space origin"] = "(" + v + ",0,0)";
    nrrd(v + "-origin.nrrd", "non-finite space origin", f);
    f = lps;
    f["space directions"] = "(1,0,0) (0," + v + ",0) (0,0,1)";
    nrrd(v + "-direction.nrrd", "non-finite space direction", f);
  }
  {
    auto f = lps;
    f["space directions"] = "(1,0,0) (0,0,0) (0,0,1)";
    nrrd("zero-direction.nrrd", "length 0", f);
  }
  nrrd("bad-type.nrrd", "unsupported NRRD type", {{"type", "block"}});
  nrrd("no-type.nrrd", "lacks dimension, sizes or type", {{"type", "-"}});
  nrrd("uchar.nrrd", "8-bit", {{"type", "uchar"}}, std::string(64, '\x80'));
  nrrd("truncated.nrrd", "truncated", {}, Voxels(20));
  nrrd("empty-data.nrrd", "truncated", {}, "");
  nrrd("bad-encoding.nrrd", "encoding", {{"encoding", "zip"}});
  nrrd("abs-data.nhdr", "absolute path", {{"data file", "/etc/passwd"}});
  nrrd("parent-data.nhdr", "'..'", {{"data file", "../secret.raw"}});
  nrrd("list-data.nhdr", "list or pattern", {{"data file", "LIST"}});
  nrrd("pattern-data.nhdr", "list or pattern", {{"data file", "slice%03d.raw 1 4 1"}});
  nrrd("missing-data.nhdr", "does not exist", {{"data file", "nothing.raw"}});
  Import("devzero.nhdr", {"devzero.nhdr", "is a device"},
         Writes("devzero.nhdr", Nrrd({{"data file", "/dev/zero"}})), {"--allow-outside-data"});
  Import("short-data.nhdr", {"truncated"}, [](const fs::path& in) {
    WriteFile(in / "short.raw", Voxels(10));
    WriteFile(in / "short-data.nhdr", Nrrd({{"data file", "short.raw"}}));
  });
  Import("folder-data.nhdr", {"is a folder"}, [](const fs::path& in) {
    fs::create_directory(in / "sub");
    WriteFile(in / "folder-data.nhdr", Nrrd({{"data file", "sub"}}));
  });
  Import("link-out.nhdr", {"outside the header's folder"}, [](const fs::path& in) {
    WriteFile(in.parent_path() / "elsewhere.raw", Voxels());
    fs::create_symlink("../elsewhere.raw", in / "link.raw");
    WriteFile(in / "link-out.nhdr", Nrrd({{"data file", "link.raw"}}));
  });
  Import("gzip-cut.nrrd", {"gzip-cut.nrrd"}, [](const fs::path& in) {
    WriteGzip(in / "v.gz", Voxels());
    const std::string gz = ReadFile(in / "v.gz");
    fs::remove(in / "v.gz");
    WriteFile(in / "gzip-cut.nrrd", Nrrd({{"encoding", "gzip"}}, gz.substr(0, gz.size() / 2)));
  });
  Import("gzip-garbage.nrrd", {"gzip-garbage.nrrd"},
         Writes("gzip-garbage.nrrd", Nrrd({{"encoding", "gzip"}}, std::string(200, 'z'))));
  {
    std::string kv = "NRRD0004\n";
    for (int i = 0; i < 20000; ++i)
      kv.append("k").append(std::to_string(i)).append(":=v\n");
    kv.append(Nrrd({}).substr(9));
    Import("many-lines.nrrd", {"more than 4096 lines"}, Writes("many-lines.nrrd", kv));
  }
  Import("long-line.nrrd", {"header is longer than"},
         Writes("long-line.nrrd", "NRRD0004\n" + std::string(3 << 20, 'a')));
  Import("text.nrrd", {"not a NRRD file"}, Writes("text.nrrd", "hello\n"));
  Import("empty.nrrd", {"not a NRRD file"}, Writes("empty.nrrd", ""));
  Import("nan-voxels.nrrd", {"non-finite voxel value"}, [](const fs::path& in) {
    std::string data;
    for (int i = 0; i < 64; ++i) {
      const float v = i == 5 ? kNaN : -1000.0f + 40.0f * float(i);
      data.append(reinterpret_cast<const char*>(&v), 4);
    }
    WriteFile(in / "nan-voxels.nrrd", Nrrd({{"type", "float"}}, data));
  });
  Import("inf-voxels.nrrd", {"non-finite voxel value"}, [](const fs::path& in) {
    std::string data;
    for (int i = 0; i < 64; ++i) {
      const float v = i == 9 ? kInf : -1000.0f + 40.0f * float(i);
      data.append(reinterpret_cast<const char*>(&v), 4);
    }
    WriteFile(in / "inf-voxels.nrrd", Nrrd({{"type", "float"}}, data));
  });
  Import("fifo.nrrd", {"FIFO"},
         [](const fs::path& in) { ::mkfifo((in / "fifo.nrrd").c_str(), 0600); });
  Import("folder.nrrd", {"folder.nrrd"},
         [](const fs::path& in) { fs::create_directory(in / "folder.nrrd"); });
  Import("missing.nrrd", {"missing.nrrd"}, {});
  Import("unknown.xyz", {"unknown.xyz"}, Writes("unknown.xyz", "data"));

  auto mha = [](const std::string& name, const std::string& needle,
                std::map<std::string, std::string> f, std::string data = Voxels()) {
    Import(name, {name, needle}, Writes(name, Mha(f, data)));
  };
  mha("etc-passwd.mha", "absolute path", {{"ElementDataFile", "/etc/passwd"}});
  mha("dotdot.mhd", "'..'", {{"ElementDataFile", "../../../../../../../../etc/passwd"}});
  mha("4d.mha", "4-D", {{"NDims", "4"}, {"DimSize", "4 4 4 2"}});
  mha("2d.mha", "2-D", {{"NDims", "2"}, {"DimSize", "4 4"}});
  mha("word-ndims.mha", "-D image", {{"NDims", "three"}});
  mha("zero-dim.mha", "size", {{"DimSize", "4 0 4"}});
  mha("neg-dim.mha", "size", {{"DimSize", "4 -4 4"}});
  mha("huge.mha", "more than the", {{"DimSize", "70000 70000 70000"}});
  mha("truncated.mha", "truncated", {}, Voxels(30));
  for (const std::string v : {"nan", "inf"}) {
    mha(v + "-spacing.mha", "non-finite voxel spacing", {{"ElementSpacing", "1 " + v + " 1"}});
    mha(v + "-offset.mha", "non-finite origin", {{"Offset", "0 0 " + v}});
    mha(v + "-transform.mha", "non-finite direction",
        {{"TransformMatrix", "1 0 0 0 " + v + " 0 0 0 1"}});
  }
  mha("zero-spacing.mha", "voxel spacing of 0", {{"ElementSpacing", "0 1 1"}});
  mha("neg-spacing.mha", "voxel spacing of -2", {{"ElementSpacing", "-2 1 1"}});
  mha("tiny-transform.mha", "is zero (or nearly", {{"TransformMatrix", "1e-300 0 0 0 1 0 0 0 1"}});
  mha("zero-transform.mha", "direction axis 1 is zero", {{"TransformMatrix", "1 0 0 0 0 0 0 0 1"}});
  mha("list.mha", "list or pattern", {{"ElementDataFile", "LIST"}});
  mha("channels.mha", "components per voxel", {{"ElementNumberOfChannels", "3"}});
  mha("bad-type.mha", "unsupported ElementType", {{"ElementType", "MET_STRING"}});
  mha("compressed-cut.mha", "truncated",
      {{"CompressedData", "True"}, {"CompressedDataSize", "100000"}}, "xx");
  Import("is-nrrd.mha", {"NRRD file, not a MetaImage"}, Writes("is-nrrd.mha", Nrrd({})));
  Import("garbage.mha", {"not 'Key = Value'"},
         Writes("garbage.mha", std::string("\x01\x02\x03 binary\n", 11)));
  Import("no-datafile.mha", {"no ElementDataFile"},
         Writes("no-datafile.mha", "NDims = 3\nDimSize = 4 4 4\n"));
  Import("fifo.mha", {"FIFO"},
         [](const fs::path& in) { ::mkfifo((in / "fifo.mha").c_str(), 0600); });
  Import("short-raw.mhd", {"truncated"}, [](const fs::path& in) {
    WriteFile(in / "v.raw", Voxels(7));
    WriteFile(in / "short-raw.mhd", Mha({{"ElementDataFile", "v.raw"}}));
  });

  auto nii = [](const std::string& name, const std::string& needle, std::function<void(char*)> edit,
                std::string data = Voxels()) {
    Import(name, {name, needle}, Writes(name, Nifti(edit, data)));
  };
  nii("nan-pixdim.nii", "non-finite pixdim", [](char* h) { PutFloat(h, 80, kNaN); });
  nii("inf-pixdim.nii", "non-finite pixdim", [](char* h) { PutFloat(h, 84, kInf); });
  nii("zero-pixdim.nii", "voxel spacing of 0", [](char* h) { PutFloat(h, 88, 0); });
  nii("nan-slope.nii", "non-finite rescale", [](char* h) { PutFloat(h, 112, kNaN); });
  nii("inf-inter.nii", "non-finite rescale", [](char* h) { PutFloat(h, 116, -kInf); });
  nii("4d.nii", "4-D", [](char* h) {
    PutShort(h, 40, 4);
    PutShort(h, 48, 3);
  });
  nii("2d.nii", "2-D", [](char* h) { PutShort(h, 40, 2); });
  nii("bad-dim0.nii", "dim[0]", [](char* h) { PutShort(h, 40, 9); });
  nii("zero-dim0.nii", "dim[0]", [](char* h) { PutShort(h, 40, 0); });
  nii("neg-size.nii", "not positive", [](char* h) { PutShort(h, 44, -4); });
  nii("zero-size.nii", "not positive", [](char* h) { PutShort(h, 42, 0); });
  nii("huge.nii", "more than the", [](char* h) {
    PutShort(h, 42, 32767);
    PutShort(h, 44, 32767);
    PutShort(h, 46, 32767);
  });
  nii("rgb.nii", "not a scalar type", [](char* h) { PutShort(h, 70, 128); });
  nii("complex.nii", "not a scalar type", [](char* h) { PutShort(h, 70, 32); });
  nii("nan-qform.nii", "non-finite qform", [](char* h) {
    PutShort(h, 252, 1);
    PutFloat(h, 268, kNaN);
  });
  nii("inf-qoffset.nii", "non-finite qform", [](char* h) {
    PutShort(h, 252, 1);
    PutFloat(h, 276, kInf);
  });
  nii("nan-sform.nii", "non-finite sform", [](char* h) {
    PutShort(h, 254, 1);
    PutFloat(h, 300, kNaN);
  });
  nii("nan-offset.nii", "vox_offset", [](char* h) { PutFloat(h, 108, kNaN); });
  nii("bad-magic.nii", "magic n+1", [](char* h) { std::memcpy(h + 344, "xyz", 4); });
  nii("truncated.nii", "truncated", {}, Voxels(40));
  nii("header-only.nii", "truncated", {}, "");
  Import("short.nii", {"too short"}, Writes("short.nii", std::string(100, 'x')));
  Import("not-nifti.nii", {"not a NIfTI-1 file"}, Writes("not-nifti.nii", std::string(400, 'x')));
  Import("truncated.nii.gz", {"truncated.nii.gz"},
         [](const fs::path& in) { WriteGzip(in / "truncated.nii.gz", Nifti({}, Voxels(30))); });
  Import("gz-cut.nii.gz", {"gz-cut.nii.gz"}, [](const fs::path& in) {
    WriteGzip(in / "gz-cut.nii.gz", Nifti());
    fs::resize_file(in / "gz-cut.nii.gz", fs::file_size(in / "gz-cut.nii.gz") / 2);
  });
  Import("nan-pixdim.nii.gz", {"non-finite pixdim"}, [](const fs::path& in) {
    WriteGzip(in / "nan-pixdim.nii.gz", Nifti([](char* h) { PutFloat(h, 80, kNaN); }));
  });

  // InVesalius projects.
  auto inv3 = [](const std::string& name, const std::string& needle, std::string tar) {
    Import(name, {name, needle}, [=](const fs::path& in) { WriteGzip(in / name, tar); });
  };
  Import("text.inv3", {"not a readable InVesalius project"}, Writes("text.inv3", "not a tar"));
  inv3("no-plist.inv3", "holds no main.plist", TarMember("a.txt", "x"));
  inv3("neg-shape.inv3", "not a whole number",
       Inv3(Plist("<integer>-4</integer><integer>4</integer><integer>4</integer>")));
  Import("huge-shape.inv3", {"more than the"}, [](const fs::path& in) {
    WriteGzip(
        in / "huge-shape.inv3",
        Inv3(Plist("<integer>900000</integer><integer>900000</integer><integer>900000</integer>")));
  });
  inv3("nan-spacing.inv3", "invalid voxel spacing",
       Inv3(Plist("<integer>4</integer><integer>4</integer><integer>4</integer>",
                  "<real>nan</real><real>1</real><real>1</real>")));
  Import("long-tag.inv3", {"main.plist", "implausibly long"}, [](const fs::path& in) {
    WriteGzip(in / "long-tag.inv3", Inv3("<plist><" + std::string(200000, 'a') + ">"));
  });
  inv3("short-matrix.inv3", "bytes", Inv3(Plist(), Voxels(10)));
}

void VtkCases() {
  auto legacy = [](const std::string& dims, const std::string& spacing, const std::string& body,
                   const std::string& mode = "ASCII") {
    return "# vtk DataFile Version 3.0\nhostile\n" + mode +
           "\nDATASET STRUCTURED_POINTS\nDIMENSIONS " + dims + "\nSPACING " + spacing +
           "\nORIGIN 0 0 0\nPOINT_DATA 64\nSCALARS ct short\nLOOKUP_TABLE default\n" + body;
  };
  std::string ascii;
  for (int i = 0; i < 64; ++i)
    ascii += (i >= 21 && i <= 42) ? "1000 " : "-1000 ";
  auto vtk = [](const std::string& name, const std::vector<std::string>& needles,
                const std::string& text) { Import(name, needles, Writes(name, text)); };
  vtk("nan-spacing.vtk", {"nan-spacing.vtk"}, legacy("4 4 4", "nan 1 1", ascii));
  vtk("zero-spacing.vtk", {"zero-spacing.vtk", "spacing"}, legacy("4 4 4", "0 1 1", ascii));
  vtk("neg-spacing.vtk", {"neg-spacing.vtk", "spacing"}, legacy("4 4 4", "-1 1 1", ascii));
  vtk("huge-dims.vtk", {"huge-dims.vtk"}, legacy("100000 100000 100000", "1 1 1", ascii));
  vtk("few-values.vtk", {"few-values.vtk"}, legacy("4 4 4", "1 1 1", "1 2 3"));
  vtk("word-values.vtk", {"word-values.vtk"}, legacy("4 4 4", "1 1 1", "a b c d"));
  vtk("binary-cut.vtk", {"binary-cut.vtk"}, legacy("4 4 4", "1 1 1", "ab", "BINARY"));
  vtk("no-data.vtk", {"no-data.vtk"}, legacy("4 4 4", "1 1 1", "").substr(0, 90));
  vtk("polydata.vtk", {"polydata.vtk"},
      "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\n");
  vtk("text.vtk", {"text.vtk"}, "hello\n");
  vtk("empty.vtk", {"empty.vtk"}, "");
  auto vti = [](const std::string& spacing, const std::string& extent, const std::string& data) {
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<ImageData WholeExtent=\"" +
           extent + "\" Origin=\"0 0 0\" Spacing=\"" + spacing + "\">\n<Piece Extent=\"" + extent +
           "\"><PointData Scalars=\"ct\"><DataArray type=\"Int16\" Name=\"ct\" "
           "format=\"ascii\">" +
           data + "</DataArray></PointData></Piece></ImageData></VTKFile>\n";
  };
  vtk("nan-spacing.vti", {"nan-spacing.vti"}, vti("nan 1 1", "0 3 0 3 0 3", ascii));
  vtk("zero-spacing.vti", {"zero-spacing.vti", "spacing"}, vti("0 1 1", "0 3 0 3 0 3", ascii));
  vtk("few-values.vti", {"few-values.vti"}, vti("1 1 1", "0 3 0 3 0 3", "1 2 3"));
  vtk("huge-extent.vti", {"huge-extent.vti"}, vti("1 1 1", "0 99999 0 99999 0 99999", ascii));
  vtk("inverted-extent.vti", {"inverted-extent.vti"}, vti("1 1 1", "3 0 0 3 0 3", ascii));
  vtk("garbage.vti", {"garbage.vti"}, "garbage");
  vtk("cut.vti", {"cut.vti"}, vti("1 1 1", "0 3 0 3 0 3", ascii).substr(0, 200));
  vtk("empty.vti", {"empty.vti"}, "");
}

void DicomCases() {
  const fs::path base = gBase / "ct";
  const auto files = Slices(base);
  const size_t mid = files.size() / 2;
  auto series = [&](const std::string& name, const std::vector<std::string>& needles, long which,
                    uint16_t g, uint16_t e, const std::string& value) {
    Import(name, needles, [=](const fs::path& in) {
      fs::copy(base, in / name);
      const auto copies = Slices(in / name);
      for (size_t i = 0; i < copies.size(); ++i)
        if (which < 0 || size_t(which) == i)
          SetDicomValue(copies[i], g, e, value);
    });
  };
  const long m = long(mid);
  series("nan-position", {"non-finite ImagePositionPatient"}, m, 0x0020, 0x0032, "0\\nan\\3");
  series("inf-position", {"non-finite ImagePositionPatient"}, m, 0x0020, 0x0032, "inf\\0\\3");
  series("word-position", {"ImagePositionPatient"}, m, 0x0020, 0x0032, "a\\b\\c");
  series("short-position", {"ImagePositionPatient"}, m, 0x0020, 0x0032, "1\\2");
  series("nan-orientation", {"non-finite ImageOrientationPatient"}, -1, 0x0020, 0x0037,
         "1\\0\\0\\0\\nan\\0");
  series("zero-orientation", {"ImageOrientationPatient"}, -1, 0x0020, 0x0037, "0\\0\\0\\0\\0\\0");
  series("tilted-slice", {"orientation different"}, m, 0x0020, 0x0037, "1\\0\\0\\0\\0.8\\0.6");
  series("nan-slope", {"RescaleSlope"}, m, 0x0028, 0x1053, "nan");
  series("zero-slope", {"RescaleSlope (0028,1053) of 0"}, -1, 0x0028, 0x1053, "0");
  series("inf-intercept", {"RescaleIntercept"}, m, 0x0028, 0x1052, "-inf");
  series("mixed-modality", {"unlike the series' first slice"}, m, 0x0008, 0x0060, "MR");
  series("mr-series", {"modality"}, -1, 0x0008, 0x0060, "MR");
  series("other-spacing", {"pixel spacing different"}, m, 0x0028, 0x0030, "0.7\\0.7");
  series("nan-spacing", {"PixelSpacing"}, -1, 0x0028, 0x0030, "nan\\0.5");
  series("zero-spacing", {"PixelSpacing"}, -1, 0x0028, 0x0030, "0\\0.5");
  auto edit = [&](const std::string& name, const std::vector<std::string>& needles,
                  std::function<void(const std::vector<fs::path>&)> change) {
    Import(name, needles, [=](const fs::path& in) {
      fs::copy(base, in / name);
      change(Slices(in / name));
    });
  };
  edit("missing-slice", {"inconsistent slice spacing"}, [=](const auto& c) { fs::remove(c[mid]); });
  edit("same-position", {"lie at the same position"}, [=](const auto& c) {
    fs::copy_file(c[mid], c[mid + 1], fs::copy_options::overwrite_existing);
  });
  for (uintmax_t cut : {0, 100, 131, 140, 150, 200, 260, 600})
    edit("cut-at-" + std::to_string(cut), {"cut-at-" + std::to_string(cut)},
         [=](const auto& c) { fs::resize_file(c[mid], cut); });
  edit("truncated-pixels", {"truncated"},
       [=](const auto& c) { fs::resize_file(c[mid], fs::file_size(c[mid]) - 100); });
  edit("no-preamble", {"no-preamble"}, [=](const auto& c) {
    const std::string d = ReadFile(c[mid]);
    WriteFile(c[mid], d.substr(132));
  });
  edit("fifo-slice", {"fifo-slice"}, [=](const auto& c) {
    fs::remove(c[mid]);
    ::mkfifo(c[mid].c_str(), 0600);
  });
  Import("single.dcm", {"single slice"},
         [=](const fs::path& in) { fs::copy(files[mid], in / "single.dcm"); });
  Import("cut-single.dcm", {"cut-single.dcm"}, [=](const fs::path& in) {
    fs::copy(files[mid], in / "cut-single.dcm");
    fs::resize_file(in / "cut-single.dcm", 300);
  });
  Import("empty-folder", {"empty-folder"},
         [](const fs::path& in) { fs::create_directory(in / "empty-folder"); });
  Import("text-folder", {"text-folder"}, [](const fs::path& in) {
    fs::create_directory(in / "text-folder");
    WriteFile(in / "text-folder" / "a.dcm", "not dicom");
  });
  // The output inside the input folder, and equal to the input.
  Add("import --out inside the DICOM folder",
      {"import", "{in}/ct", "--out", "{in}/ct/v.nrrd", "-q"}, {"inside the input"},
      [=](const fs::path& in) { fs::copy(base, in / "ct"); });
  Add("import --out equal to the input", {"import", "{in}/ct.nrrd", "--out", "{in}/ct.nrrd", "-q"},
      {"is the input"}, Writes("ct.nrrd", Nrrd({})));
  Add("import --out in a missing folder",
      {"import", "{in}/ct.nrrd", "--out", "{out}/no/such/v.nrrd", "-q"},
      {"no/such", "does not exist"}, Writes("ct.nrrd", Nrrd({})));
  Add("import --out of another format", {"import", "{in}/ct.nrrd", "--out", "{out}/v.png", "-q"},
      {"v.png"}, Writes("ct.nrrd", Nrrd({})));
  // The output is the header's detached data file: it would overwrite the CT's voxels.
  Add("import --out is the data file", {"import", "{in}/ct.nhdr", "--out", "{in}/vol.nrrd", "-q"},
      {"the data file of the input"}, [](const fs::path& in) {
        WriteFile(in / "vol.nrrd", Voxels());
        WriteFile(in / "ct.nhdr", Nrrd({{"data file", "vol.nrrd"}}));
      });
  Add("import --out is a link to the input",
      {"import", "{in}/ct.nrrd", "--out", "{in}/link.nrrd", "-q"}, {"is the input"},
      [](const fs::path& in) {
        WriteFile(in / "ct.nrrd", Nrrd({}));
        fs::create_symlink(in / "ct.nrrd", in / "link.nrrd");
      });
  // Refused before the work, not after it: an output name too long for its temporary's, a path
  // that is not UTF-8 (the JSON outputs are).
  Add("import --out with a 240-character name",
      {"import", "{in}/ct.nrrd", "--out", "{out}/" + std::string(240, 'a') + ".nrrd", "-q"},
      {"exceeds the file system's limit"}, Writes("ct.nrrd", Nrrd({})));
  Add("import a path that is not UTF-8", {"import", "{in}/ct\xff.nrrd", "--out", "{out}/v.nrrd"},
      {"not valid UTF-8"}, Writes("ct\xff.nrrd", Nrrd({})));
  // A damaged first slice is named.
  Add("import first slice cut before its pixels",
      {"import", "{in}/ct", "--out", "{out}/v.nrrd", "-q"},
      {"IM00001.dcm", "ends without its image"}, [=](const fs::path& in) {
        fs::copy(base, in / "ct");
        const fs::path f = in / "ct" / "IM00001.dcm";
        const std::string bytes = ReadFile(f);
        WriteFile(f, bytes.substr(0, bytes.find(std::string("\xe0\x7f\x10\x00", 4))));
      });
}

const char* kColumns =
    "frame,time_s,device_x_mm,device_y_mm,device_z_mm,device_qw,device_qx,device_qy,device_qz,"
    "proxy_x_mm,proxy_y_mm,proxy_z_mm,feed_mm_per_rev,thrust_N,torque_Nmm,coupling_fx_N,"
    "coupling_fy_N,coupling_fz_N,device_fx_N,device_fy_N,device_fz_N,frame_ms,removed_voxels,"
    "removed_volume_mm3,speed_rpm,buttons,flags";

/// A recording row with column `col` (0-based) replaced by `value`.
std::string Row(int col = -1, const std::string& value = "") {
  const std::vector<std::string> v = {"0", "0", "0", "0",    "1", "1", "0",    "0", "0",
                                      "0", "0", "1", "0.02", "0", "0", "0",    "0", "0",
                                      "0", "0", "0", "0.1",  "0", "0", "1000", "0", "0"};
  std::string s;
  for (size_t i = 0; i < v.size(); ++i)
    s += (i ? "," : "") + (int(i) == col ? value : v[i]);
  return s + "\n";
}

void SceneCases() {
  auto scene = [](const std::string& name, const std::vector<std::string>& needles,
                  const std::string& json) {
    Add("run " + name, {"run", "{in}/" + name, "--no-report"}, needles, Writes(name, json));
  };
  std::string deep(100000, '[');
  deep += std::string(100000, ']');
  scene("deep.json", {"nested deeper than 64 levels"}, deep);
  scene("deep-tool.json", {"nested deeper than 64 levels"}, "{\"tool\": " + deep + "}");
  scene("syntax.json", {"syntax.json"}, "{\"name\": ");
  scene("empty.json", {"empty.json"}, "");
  scene("array.json", {"scene must be a JSON object"}, "[1, 2]");
  scene("escape.json", {"must not start with '.'"}, "{\"name\": \"../../x\"}");
  scene("slash.json", {"must not contain '/'"}, "{\"name\": \"a/../../../x\"}");
  scene("long-name.json", {"name"}, "{\"name\": \"" + std::string(300, 'n') + "\"}");
  scene("control-name.json", {"name"}, "{\"name\": \"a\\u0001b\"}");
  scene("unknown-field.json", {"bogus"}, "{\"bogus\": 1}");
  struct Field {
    std::string name, json, needle;
  };
  const std::vector<Field> fields = {
      {"voxmap-res-big", "{\"voxmap_resolution\": 100000}", "voxmap_resolution"},
      {"voxmap-res-small", "{\"voxmap_resolution\": 2}", "voxmap_resolution"},
      {"voxmap-res-frac", "{\"voxmap_resolution\": 64.5}", "voxmap_resolution"},
      {"voxmap-res-huge", "{\"voxmap_resolution\": 1e300}", "voxmap_resolution"},
      {"voxmap-res-text", "{\"voxmap_resolution\": \"x\"}", "voxmap_resolution"},
      {"shell-res-big", "{\"shell_resolution\": 5000}", "shell_resolution"},
      {"shell-res-neg", "{\"shell_resolution\": -8}", "shell_resolution"},
      {"threads-big", "{\"threads\": 10000000000}", "threads"},
      {"threads-zero", "{\"threads\": 0}", "threads"},
      {"method", "{\"method\": \"bogus\"}", "method"},
      {"lips-word", "{\"lips\": \"bogus\"}", "lips"},
      {"backend", "{\"backend\": \"bogus\"}", "backend"},
      {"feed-big", "{\"trial\": {\"feed_mm_per_rev\": 5}}", "feed"},
      {"feed-zero", "{\"trial\": {\"feed_mm_per_rev\": 0}}", "feed"},
      {"feed-text", "{\"trial\": {\"feed_mm_per_rev\": \"fast\"}}", "feed_mm_per_rev"},
      {"speed-big", "{\"trial\": {\"speed_rpm\": 1e9}}", "speed"},
      {"speed-neg", "{\"trial\": {\"speed_rpm\": -5}}", "speed"},
      {"frame-big", "{\"trial\": {\"frame_s\": 5}}", "frame"},
      {"frame-zero", "{\"trial\": {\"frame_s\": 0}}", "frame"},
      {"clearance-big", "{\"trial\": {\"clearance_mm\": 1e9}}", "clearance"},
      {"clearance-neg", "{\"trial\": {\"clearance_mm\": -1}}", "clearance"},
      {"depth-big", "{\"trial\": {\"depth_mm\": 1e6}}", "depth"},
      {"extra-depth-neg", "{\"trial\": {\"extra_depth_mm\": -3}}", "extra"},
      {"entry-far", "{\"trial\": {\"entry_mm\": [1e9, 0, 0]}}", "entry"},
      {"entry-short", "{\"trial\": {\"entry_mm\": [0, 0]}}", "entry"},
      {"entry-text", "{\"trial\": {\"entry_mm\": \"here\"}}", "entry"},
      {"axis-zero", "{\"trial\": {\"axis\": [0, 0, 0]}}", "axis"},
      {"axis-long", "{\"trial\": {\"axis\": [0, 0, 5]}}", "axis"},
      {"axis-four", "{\"trial\": {\"axis\": [0, 0, 1, 0]}}", "axis"},
      {"block-zero", "{\"bone\": {\"type\": \"block\", \"size_mm\": [0, 5, 5]}}", "size"},
      {"block-huge", "{\"bone\": {\"type\": \"block\", \"size_mm\": [1e9, 5, 5]}}", "size"},
      {"block-short", "{\"bone\": {\"type\": \"block\", \"size_mm\": [5, 5]}}", "size"},
      {"material-neg", "{\"bone\": {\"material\": -1}}", "material"},
      {"material-huge", "{\"bone\": {\"material\": 1e38}}", "material"},
      {"bone-type", "{\"bone\": {\"type\": \"bogus\"}}", "bone"},
      {"ct-bone-empty", "{\"bone\": {\"type\": \"ct\"}}", "ct"},
      {"ct-bone-missing", "{\"bone\": {\"type\": \"ct\", \"ct\": {\"ct\": \"/no/such/ct\"}}}",
       "/no/such/ct"},
      {"tool-type", "{\"tool\": {\"type\": \"hammer\"}}", "hammer"},
      {"lips-many", "{\"tool\": {\"type\": \"reamer\", \"lips\": 10000}}", "lips"},
      {"lips-zero", "{\"tool\": {\"type\": \"reamer\", \"lips\": 0}}", "lips"},
      {"diameter-neg", "{\"tool\": {\"type\": \"drill\", \"diameter_mm\": -2}}", "diameter"},
      {"diameter-huge", "{\"tool\": {\"type\": \"drill\", \"diameter_mm\": 1e9}}", "diameter"},
      {"tool-text", "{\"tool\": {\"type\": \"drill\", \"diameter_mm\": \"big\"}}", "diameter"},
      {"tool-array", "{\"tool\": [1, 2]}", "tool"},
      {"steps-text", "{\"steps\": \"x\"}", "steps"},
      {"steps-bad", "{\"steps\": [{\"name\": \"../a\"}]}", "step"},
      {"force-model-text", "{\"force_model\": 5}", "force_model"},
      {"force-model-mixed", "{\"force_model\": {\"coefficients\": \"assumed\", \"lips\": {}}}",
       "force_model"},
      {"force-model-missing", "{\"force_model\": {\"coefficients\": \"/no/such.json\"}}",
       "/no/such.json"},
      {"force-model-basis",
       "{\"force_model\": {\"lips\": {\"basis\": [\"bogus\"], \"kc_N_per_mm2\": [1], "
       "\"kt_N_per_mm2\": [1]}}}",
       "bogus"},
      {"force-model-huge",
       "{\"force_model\": {\"lips\": {\"basis\": [\"1\"], \"kc_N_per_mm2\": [1e300], "
       "\"kt_N_per_mm2\": [1]}}}",
       "kc_N_per_mm2"},
      {"force-model-count",
       "{\"force_model\": {\"lips\": {\"basis\": [\"1\"], \"kc_N_per_mm2\": [1, 2], "
       "\"kt_N_per_mm2\": [1]}}}",
       "one value per basis term"},
  };
  for (const auto& f : fields)
    scene(f.name + ".json", {f.needle}, f.json);
  Add("run scene FIFO", {"run", "{in}/fifo.json", "--no-report"}, {"fifo.json"},
      [](const fs::path& in) { ::mkfifo((in / "fifo.json").c_str(), 0600); });
  Add("run missing scene", {"run", "{in}/none.json", "--no-report"}, {"none.json"});
  Add("run unknown built-in", {"run", "bogus-scene", "--no-report"}, {"bogus-scene"});

  // Coefficient files a scene names.
  auto coefficients = [](const std::string& name, const std::vector<std::string>& needles,
                         const std::string& json) {
    Add("run coefficients " + name, {"run", "{in}/s.json", "--no-report"}, needles,
        [=](const fs::path& in) {
          WriteFile(in / name, json);
          WriteFile(in / "s.json",
                    "{\"force_model\": {\"coefficients\": \"" + (in / name).string() + "\"}}");
        });
  };
  coefficients("deep.json", {"nested deeper than 64 levels"}, deep);
  coefficients("syntax.json", {"syntax.json"}, "{");
  coefficients("no-lips.json", {"no-lips.json", "lips"}, "{\"name\": \"x\"}");
  coefficients("lips-text.json", {"lips-text.json", "coefficients"}, "{\"lips\": 5}");
  coefficients("no-basis.json", {"no-basis.json", "basis"}, "{\"lips\": {\"k_c\": 1}}");
  coefficients(
      "basis-word.json", {"basis-word.json", "bogus"},
      "{\"lips\": {\"basis\": [\"bogus\"], \"kc_N_per_mm2\": [1], \"kt_N_per_mm2\": [1]}}");
  coefficients("basis-number.json", {"basis-number.json", "basis"},
               "{\"lips\": {\"basis\": [5], \"kc_N_per_mm2\": [1], \"kt_N_per_mm2\": [1]}}");
  coefficients(
      "kc-text.json", {"kc-text.json", "kc_N_per_mm2"},
      "{\"lips\": {\"basis\": [\"1\"], \"kc_N_per_mm2\": [\"x\"], \"kt_N_per_mm2\": [1]}}");
  coefficients(
      "kc-huge.json", {"kc-huge.json", "kc_N_per_mm2"},
      "{\"lips\": {\"basis\": [\"1\"], \"kc_N_per_mm2\": [1e300], \"kt_N_per_mm2\": [1]}}");
  coefficients("kt-count.json", {"kt-count.json", "one value per basis term"},
               "{\"lips\": {\"basis\": [\"1\"], \"kc_N_per_mm2\": [1], \"kt_N_per_mm2\": []}}");
  coefficients("method.json", {"method.json", "method"},
               "{\"method\": \"bogus\", \"lips\": {\"basis\": [\"1\"], \"kc_N_per_mm2\": [1], "
               "\"kt_N_per_mm2\": [1]}}");

  // Saved voxmaps a scene names as its bone.
  auto voxmap = [](const std::string& name, const std::vector<std::string>& needles,
                   const std::string& bytes) {
    Add("run voxmap " + name, {"run", "{in}/s.json", "--no-report"}, needles,
        [=](const fs::path& in) {
          WriteFile(in / name, bytes);
          WriteFile(in / "s.json", "{\"bone\": {\"type\": \"ct\", \"ct\": {\"voxmap\": \"" +
                                       (in / name).string() + "\"}}}");
        });
  };
  voxmap("nan-material.mha", {"holds material scale nan"}, VoxmapMha(1.0f, 9, kNaN));
  voxmap("inf-material.mha", {"holds material scale inf"}, VoxmapMha(1.0f, 9, kInf));
  voxmap("huge-material.mha", {"holds material scale 1e+38"}, VoxmapMha(1.0f, 9, 1e38f));
  voxmap("neg-material.mha", {"holds material scale -1"}, VoxmapMha(1.0f, 9, -1.0f));
  voxmap("nan-fraction.mha", {"nan-fraction.mha"}, [] {
    std::string data;
    for (int i = 0; i < 64; ++i) {
      const float v[2] = {i == 3 ? kNaN : 1.0f, 1.0f};
      data.append(reinterpret_cast<const char*>(v), sizeof v);
    }
    return Mha({{"ElementType", "MET_FLOAT"}, {"ElementNumberOfChannels", "2"}}, data);
  }());
  voxmap("nrrd-named.mha", {"is a NRRD file, not a MetaImage"}, Nrrd({}));
  voxmap("passwd.mha", {"absolute path"},
         VoxmapMha(1.0f, -1, 1.0f, {{"ElementDataFile", "/etc/passwd"}}));
  voxmap("three.mha", {"3 components per voxel"},
         VoxmapMha(1.0f, -1, 1.0f, {{"ElementNumberOfChannels", "3"}}));
  voxmap("nan-spacing.mha", {"non-finite voxel spacing"},
         VoxmapMha(1.0f, -1, 1.0f, {{"ElementSpacing", "nan 1 1"}}));
  voxmap("cut.mha", {"truncated"}, VoxmapMha(1.0f).substr(0, 400));
  voxmap("huge.mha", {"huge.mha"}, VoxmapMha(1.0f, -1, 1.0f, {{"DimSize", "90000 90000 90000"}}));
  voxmap("voxmap.vtk", {"a voxmap is .nrrd, .nhdr, .mha or .mhd"}, "# vtk DataFile\n");
  voxmap("garbage.nrrd", {"not a NRRD file"}, "garbage");

  // Trajectory files of the scripted device.
  auto trajectory = [](const std::string& name, const std::vector<std::string>& needles,
                       const std::string& text) {
    Add("run trajectory " + name,
        {"run", "drilling", "--out", "{out}/t", "--no-report", "--device", "scripted", "--mode",
         "trajectory", "--trajectory", "{in}/" + name},
        needles, Writes(name, text));
  };
  const std::string head = "time_s,x_mm,y_mm,z_mm\n";
  trajectory("nan.csv", {"nan.csv:3", "finite"}, head + "0,0,0,1\n1,nan,0,1\n");
  trajectory("nan-z.csv", {"nan-z.csv:3", "finite"}, head + "0,0,0,1\n1,0,0,nan\n");
  trajectory("one-sample.csv", {"one-sample.csv", "at least 2 samples"}, head + "0,0,0,1\n");
  trajectory("empty.csv", {"empty.csv", "at least 2 samples"}, head);
  trajectory("long-time.csv", {"long-time.csv:3", "time_s"}, head + "0,0,0,1\n1e300,0,0,1\n");
  trajectory("neg-time.csv", {"neg-time.csv:2", "time_s"}, head + "-5,0,0,1\n1,0,0,1\n");
  trajectory("far.csv", {"far.csv:3", "position"}, head + "0,0,0,1\n1,1e9,0,1\n");
  trajectory("back-time.csv", {"back-time.csv:3", "times must increase"},
             head + "1,0,0,1\n0.5,0,0,1\n");
  trajectory("columns.csv", {"columns.csv:2", "4 or 8 columns"}, head + "0,0,0\n");
  trajectory("word.csv", {"word.csv:2"}, head + "0,0,zero,1\n1,0,0,1\n");
  trajectory("zero-quat.csv", {"zero-quat.csv:2", "quaternion"},
             "time_s,x,y,z,qw,qx,qy,qz\n0,0,0,1,0,0,0,0\n1,0,0,1,1,0,0,0\n");
  Add("run trajectory FIFO",
      {"run", "drilling", "--out", "{out}/t", "--no-report", "--device", "scripted", "--mode",
       "trajectory", "--trajectory", "{in}/fifo.csv"},
      {"fifo.csv", "not a regular file"},
      [](const fs::path& in) { ::mkfifo((in / "fifo.csv").c_str(), 0600); });
  Add("run --record in a missing folder",
      {"run", "drilling", "--out", "{out}/r", "--no-report", "--device", "scripted", "--record",
       "{out}/no/such/rec.csv"},
      {"--record"});
  Add("run --out is a file", {"run", "drilling", "--out", "{in}/file", "--no-report"},
      {"--out", "is a file, expected a folder"}, Writes("file", "x"));
  // No output may name an input (through links too) or another output of the run.
  const std::vector<std::string> session = {"--no-report", "--device", "scripted", "--duration",
                                            "0.005"};
  auto run = [&](std::vector<std::string> args) {
    args.insert(args.end(), session.begin(), session.end());
    return args;
  };
  Add("run --record is the scene file",
      run({"run", "{in}/s.json", "--out", "{out}/r", "--record", "{in}/s.json"}),
      {"--record", "is the scene file"}, Writes("s.json", "{\"name\": \"s\"}"));
  Add("run --record is a link to the scene file",
      run({"run", "{in}/s.json", "--out", "{out}/r", "--record", "{in}/link.csv"}),
      {"--record", "is the scene file", "through a link"}, [](const fs::path& in) {
        WriteFile(in / "s.json", "{\"name\": \"s\"}");
        fs::create_symlink(in / "s.json", in / "link.csv");
      });
  Add("run --record is the trajectory",
      run({"run", "drilling", "--out", "{out}/r", "--mode", "trajectory", "--trajectory",
           "{in}/t.csv", "--record", "{in}/t.csv"}),
      {"--record", "is the --trajectory file"},
      Writes("t.csv", "time_s,x_mm,y_mm,z_mm\n0,0,0,1\n0.01,0,0,0.9\n"));
  Add("run longer than a recording holds",
      {"run", "drilling", "--out", "{out}/r", "--no-report", "--device", "scripted", "--rate",
       "10000", "--duration", "361"},
      {"a recording holds at most 3600000"});
  Add("run a hand at 10 Hz",
      {"run", "drilling", "--out", "{out}/r", "--no-report", "--device", "scripted", "--mode",
       "hand", "--rate", "10"},
      {"passive only above 50 Hz"});
  Add("run --record is a file the run writes",
      run({"run", "drilling", "--out", "{in}/r", "--record", "{in}/r/session.csv"}),
      {"--record", "a file this run writes"},
      [](const fs::path& in) { fs::create_directory(in / "r"); });
  const fs::path base = gBase / "ct";
  Add("run --record is a slice of the scene's CT",
      run({"run", "{in}/ct.json", "--out", "{out}/r", "--record", "{in}/ct/IM00002.dcm"}),
      {"--record", "inside the scene's CT folder"}, [=](const fs::path& in) {
        fs::copy(base, in / "ct");
        WriteFile(in / "ct.json", "{\"name\": \"c\", \"bone\": {\"type\": \"ct\", \"ct\": "
                                  "{\"ct\": \"ct\"}}}");
      });
}

void RecordingCases() {
  auto recording = [](const std::string& name, const std::vector<std::string>& needles,
                      const std::string& text) {
    Add("replay " + name, {"replay", "{in}/" + name, "--out", "{out}/rp"}, needles,
        Writes(name, text));
  };
  const std::string head = "# bmsession {\"scene\": {}}\n" + std::string(kColumns) + "\n";
  std::string deep(100000, '[');
  deep += std::string(100000, ']');
  recording("deep.csv", {"nested deeper than 64 levels"},
            "# bmsession {\"scene\": " + deep + "}\n");
  recording("no-header.csv", {"no-header.csv"}, std::string(kColumns) + "\n" + Row());
  recording("bad-json.csv", {"bad-json.csv"}, "# bmsession {\"scene\": \n" + std::string(kColumns));
  recording("empty.csv", {"no frames"}, head);
  recording("zero-bytes.csv", {"zero-bytes.csv"}, "");
  recording("sdf.csv", {"'sdf_resolution' must be in [8, 512], got 4096"},
            "# bmsession {\"scene\": {}, \"session\": {\"sdf_resolution\": 4096}}\n" +
                std::string(kColumns) + "\n" + Row());
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, std::string>>{{"rate_hz", "0"},
                                                        {"rate_hz", "1e12"},
                                                        {"force_scale", "1e9"},
                                                        {"force_scale", "0"},
                                                        {"max_iterations", "100000"},
                                                        {"sdf_resolution", "\"x\""},
                                                        {"sdf_resolution", "2"}})
    recording("session-" + key + "-" + value.substr(0, 3) + ".csv", {key},
              "# bmsession {\"scene\": {}, \"session\": {\"" + key + "\": " + value + "}}\n" +
                  std::string(kColumns) + "\n" + Row());
  recording("scene-lips.csv", {"lips"},
            "# bmsession {\"scene\": {\"tool\": {\"type\": \"reamer\", \"lips\": 10000}}}\n" +
                std::string(kColumns) + "\n" + Row());
  const std::vector<std::pair<int, std::string>> cells = {
      {13, "nan"},  {14, "inf"}, {2, "nan"}, {4, "-inf"},  {5, "nan"},  {24, "nan"}, {0, "1.5"},
      {0, "1e300"}, {22, "nan"}, {25, "-1"}, {26, "1e20"}, {15, "nan"}, {13, "x"},   {1, "1x"}};
  for (const auto& [col, value] : cells)
    recording(
        "cell-" + std::to_string(col) + "-" + value + ".csv",
        {col == 0 || col == 1 || (col >= 22 && col != 24) || value == "x" ? ".csv:" : "non-finite"},
        head + Row() + Row(col, value));
  recording("columns.csv", {"columns.csv"}, head + "0,1,2\n");
  recording("long-line.csv", {"long-line.csv"}, head + std::string(17 << 20, '1') + "\n");
  Add("replay FIFO", {"replay", "{in}/fifo.csv", "--out", "{out}/rp"}, {"not a regular file"},
      [](const fs::path& in) { ::mkfifo((in / "fifo.csv").c_str(), 0600); });
  Add("replay folder", {"replay", "{in}/dir.csv", "--out", "{out}/rp"}, {"dir.csv"},
      [](const fs::path& in) { fs::create_directory(in / "dir.csv"); });
  Add("replay missing", {"replay", "{in}/none.csv", "--out", "{out}/rp"}, {"none.csv"});
  Add("replay --out holding the recording", {"replay", "{in}/rp/replay.csv", "--out", "{in}/rp"},
      {"is the recording"}, [=](const fs::path& in) {
        fs::create_directory(in / "rp");
        WriteFile(in / "rp" / "replay.csv", head + Row());
      });
  // HDF5 recordings: a real one made by bmsim, then damaged.
  const fs::path h5 = gBase / "rec.h5";
  if (fs::exists(h5)) {
    const std::string bytes = ReadFile(h5);
    auto hdf5 = [](const std::string& name, const std::vector<std::string>& needles,
                   const std::string& content) {
      Add("replay " + name, {"replay", "{in}/" + name, "--out", "{out}/rp"}, needles,
          Writes(name, content));
    };
    hdf5("cut-half.h5", {"cut-half.h5"}, bytes.substr(0, bytes.size() / 2));
    hdf5("cut-header.h5", {"cut-header.h5"}, bytes.substr(0, 100));
    hdf5("zeroed.h5", {"zeroed.h5"}, std::string(bytes.size(), '\0'));
    hdf5("text.h5", {"text.h5"}, "not an HDF5 file\n");
    hdf5("empty.h5", {"empty.h5"}, "");
    std::string flipped = bytes;
    for (size_t i = 512; i < flipped.size(); i += 97)
      flipped[i] = char(~flipped[i]);
    hdf5("flipped.h5", {"flipped.h5"}, flipped);
  }
}

} // namespace

bool MakeBase() {
  fs::remove_all(gBase);
  fs::create_directories(gBase);
  const std::string phantom =
      gBmsim + " phantom block --noise 0 -q --out '" + (gBase / "ct").string() + "' > /dev/null";
  if (std::system(phantom.c_str()) != 0 || Slices(gBase / "ct").size() < 4) {
    std::cerr << "could not write the DICOM series the corpus starts from: " << phantom << "\n";
    return false;
  }
  const std::string record = gBmsim +
                             " run drilling --device scripted --duration 0.005 --no-report "
                             "--record '" +
                             (gBase / "rec.h5").string() + "' --out '" + (gBase / "run").string() +
                             "' > /dev/null 2>&1";
  if (std::system(record.c_str()) != 0)
    std::cout << "no HDF5 recording (a build without HDF5): its cases are left out\n";
  return true;
}

void FileCases() {
  VolumeCases();
  VtkCases();
  DicomCases();
  SceneCases();
  RecordingCases();
  TableCases();
}

} // namespace bmcorpus
