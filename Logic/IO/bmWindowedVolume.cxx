// bmWindowedVolume.cxx - see bmWindowedVolume.h.
#include "bmWindowedVolume.h"

#include "bmAtomicFile.h"
#include "bmProgress.h"

#include <itkImageFileWriter.h>
#include <itkMetaImageIO.h>
#include <itkNrrdImageIO.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace bm {

unsigned char WindowedValue(float hu, double centre, double width) {
  const double v = std::round(255.0 * (double(hu) - (centre - 0.5 * width)) / width);
  return static_cast<unsigned char>(std::clamp(v, 0.0, 255.0));
}

std::array<double, 2> WindowToHUMapping(double centre, double width) {
  return {width / 255.0, centre - 0.5 * width};
}

void SaveWindowedVolume(const CTImage& ct, double centre, double width, const std::string& path) {
  if (!(width > 0) || !std::isfinite(width) || !std::isfinite(centre))
    throw std::invalid_argument("window: the width must be > 0 HU and both values finite");
  const std::string ext = std::filesystem::path(path).extension().string();
  const bool nrrd = ext == ".nrrd";
  if (!nrrd && ext != ".mha")
    throw std::invalid_argument("an 8-bit volume is saved as .nrrd or .mha (one file), not '" +
                                path + "'");
  using ByteImage = itk::Image<unsigned char, 3>;
  auto out = ByteImage::New();
  out->SetRegions(ct.hu->GetLargestPossibleRegion());
  out->SetSpacing(ct.hu->GetSpacing());
  out->SetOrigin(ct.hu->GetOrigin());
  out->SetDirection(ct.hu->GetDirection());
  out->Allocate();
  const float* in = ct.hu->GetBufferPointer();
  unsigned char* o = out->GetBufferPointer();
  const size_t n = ct.hu->GetLargestPossibleRegion().GetNumberOfPixels();
  for (size_t i = 0; i < n; ++i)
    o[i] = WindowedValue(in[i], centre, width);
  // Written under a temporary name beside the target, then renamed into place.
  const std::string tmp = TemporarySibling(path); // keeps the extension
  auto writer = itk::ImageFileWriter<ByteImage>::New();
  writer->SetInput(out);
  if (nrrd)
    writer->SetImageIO(itk::NrrdImageIO::New());
  else
    writer->SetImageIO(itk::MetaImageIO::New());
  writer->SetFileName(tmp);
  writer->SetUseCompression(true);
  try {
    RunFilter(writer, Progress(), "writing the 8-bit volume to " + path);
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

} // namespace bm
