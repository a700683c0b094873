// Fuzz target: one DICOM file through the CT reader (bm::ReadCT): the project's element walk,
// GDCM's header parse and, for a file that passes, the series checks. The input is written as the
// only file of a folder (read as a series: ListDicomSeries, then ReadCT of the folder) and read
// again as a single file. Seeds: a slice of the block phantom (bmfuzz_make_ct_seeds writes them).
#include <stdexcept>

#include "bmCTReader.h"
#include "bmFuzzScratch.h"
#include "bmFuzzTarget.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool folderMade =
      std::filesystem::create_directories(bmfuzz::ScratchFolder() / "series"); // once per process
  (void)folderMade;
  const std::string file = bmfuzz::WriteInput("series/slice.dcm", data, size);
  const std::string folder = std::filesystem::path(file).parent_path().string();
  bm::ReadOptions options;
  options.maxMemoryBytes = uint64_t(256) << 20;
  for (const std::string& path : {folder, file}) {
    try {
      if (path == folder)
        (void)bm::ListDicomSeries(folder);
      (void)bm::ReadCT(path, options);
    } catch (const std::exception&) {
      // refused
    }
  }
  return 0;
}
