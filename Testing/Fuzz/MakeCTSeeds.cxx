// bmfuzz_make_ct_seeds OUT_DIR - writes the seeds of the DICOM, NIfTI and MetaImage fuzz targets,
// so that no binary file is kept in the repository: OUT_DIR/dicom/ (three slices of the block
// phantom written by the project's DICOM writer, one of them also with sequences of undefined
// length and nested items, as real CTs carry them, and one RLE-compressed: encapsulated pixel
// data), OUT_DIR/nifti/ (a 4 x 4 x 4 int16 image as .nii and as .nii.gz, each behind the
// target's one-byte selector) and OUT_DIR/metaimage/ (the image raw and zlib-compressed).
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "bmHostileFiles.h"
#include "bmIOTestUtil.h"
#include "bmPhantom.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: bmfuzz_make_ct_seeds OUT_DIR\n";
    return 2;
  }
  const fs::path out = argv[1];
  fs::remove_all(out);
  fs::create_directories(out / "nifti");
  bm::WritePhantomSeries("block", (out / "series").string(), {}, {});
  std::vector<fs::path> slices;
  for (const auto& e : fs::directory_iterator(out / "series"))
    slices.push_back(e.path());
  std::sort(slices.begin(), slices.end());
  fs::create_directories(out / "dicom");
  for (size_t i : {size_t(0), slices.size() / 2, slices.size() - 1})
    fs::copy_file(slices[i], out / "dicom" / slices[i].filename());
  fs::copy_file(slices[slices.size() / 2], out / "dicom" / "sequences.dcm");
  bmtest::EditDicom(out / "dicom" / "sequences.dcm", bmtest::AddUndefinedLengthSequence);
  fs::remove_all(out / "series");
  bm::DicomWriteOptions rle;
  rle.transferSyntax = "rle";
  bm::WritePhantomSeries("block", (out / "series").string(), {}, rle);
  slices.clear();
  for (const auto& e : fs::directory_iterator(out / "series"))
    slices.push_back(e.path());
  std::sort(slices.begin(), slices.end());
  fs::copy_file(slices[slices.size() / 2], out / "dicom" / "rle.dcm");
  fs::remove_all(out / "series");
  fs::create_directories(out / "metaimage");
  bmtest::WriteFile(out / "metaimage" / "raw.mha", bmtest::Mha({}));
  {
    const std::string voxels = bmtest::Voxels();
    uLongf size = compressBound(uLong(voxels.size()));
    std::string z(size, '\0');
    compress2(reinterpret_cast<Bytef*>(z.data()), &size,
              reinterpret_cast<const Bytef*>(voxels.data()), uLong(voxels.size()), 9);
    z.resize(size);
    bmtest::WriteFile(
        out / "metaimage" / "zlib.mha",
        bmtest::Mha({{"CompressedData", "True"}, {"CompressedDataSize", std::to_string(z.size())}},
                    z));
  }
  bmtest::WriteFile(out / "nifti" / "plain.nii", "N" + bmtest::Nifti());
  bmtest::WriteGzip(out / "nifti" / "gz.tmp", bmtest::Nifti());
  bmtest::WriteFile(out / "nifti" / "gzip.nii", "Z" + bmtest::ReadFile(out / "nifti" / "gz.tmp"));
  fs::remove(out / "nifti" / "gz.tmp");
  std::cout << "seeds: " << out.string() << "/dicom (5 slices), " << out.string()
            << "/nifti (2 files), " << out.string() << "/metaimage (2 files)\n";
  return 0;
}
