// Fuzz target: a CT volume's header through bm::CheckVolumeHeader, the check that runs before ITK
// sees a file, and a saved voxmap through bm::LoadVoxmap (the check, then ITK's reader, then the
// values). The first byte picks the case ('N' NRRD, 'M' MetaImage, 'I' NIfTI header; 'V' a voxmap
// .mha, 'W' a voxmap .nrrd; anything else a NRRD header), the rest is the file; detached data
// files may only lie beside it in the scratch folder.
#include <stdexcept>

#include "bmFuzzScratch.h"
#include "bmFuzzTarget.h"
#include "bmHeaderCheck.h"
#include "bmVoxmapFile.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0)
    return 0;
  const char kind = char(data[0]);
  if (kind == 'V' || kind == 'W') {
    const std::string path =
        bmfuzz::WriteInput(kind == 'V' ? "voxmap.mha" : "voxmap.nrrd", data + 1, size - 1);
    try {
      (void)bm::LoadVoxmap(path);
    } catch (const std::exception&) {
      // refused
    }
    return 0;
  }
  const std::string format = kind == 'M' ? "MetaImage" : kind == 'I' ? "NIfTI" : "NRRD";
  const std::string name = kind == 'M' ? "input.mha" : kind == 'I' ? "input.nii" : "input.nrrd";
  const std::string path = bmfuzz::WriteInput(name, data + 1, size - 1);
  bm::HeaderLimits limits;
  limits.maxMemoryBytes = uint64_t(256) << 20;
  limits.maxComponents = 2;
  try {
    (void)bm::CheckVolumeHeader(path, format, limits);
  } catch (const std::exception&) {
    // refused
  }
  return 0;
}
