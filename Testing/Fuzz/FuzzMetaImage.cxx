// Fuzz target: a MetaImage file (.mha, data attached, raw or zlib-compressed) through the CT
// reader (bm::ReadCT): the header check (which inflates compressed data to count them), then
// ITK's MetaImage reader and the value checks. Seeds: bmfuzz_make_ct_seeds (a 4 x 4 x 4 image,
// raw and compressed).
#include <stdexcept>

#include "bmCTReader.h"
#include "bmFuzzScratch.h"
#include "bmFuzzTarget.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = bmfuzz::WriteInput("input.mha", data, size);
  bm::ReadOptions options;
  options.maxMemoryBytes = uint64_t(256) << 20;
  try {
    (void)bm::ReadCT(path, options);
  } catch (const std::exception&) {
    // refused
  }
  return 0;
}
