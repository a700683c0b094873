// Fuzz target: a NIfTI-1 file through the CT reader (bm::ReadCT): the header check, then ITK's
// NIfTI reader and the value checks. The first byte picks the file name ('Z' input.nii.gz, the
// rest gzip data; anything else input.nii), the rest is the file. Seeds: bmfuzz_make_ct_seeds.
#include <stdexcept>

#include "bmCTReader.h"
#include "bmFuzzScratch.h"
#include "bmFuzzTarget.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0)
    return 0;
  const std::string path =
      bmfuzz::WriteInput(data[0] == 'Z' ? "input.nii.gz" : "input.nii", data + 1, size - 1);
  bm::ReadOptions options;
  options.maxMemoryBytes = uint64_t(256) << 20;
  try {
    (void)bm::ReadCT(path, options);
  } catch (const std::exception&) {
    // refused
  }
  return 0;
}
