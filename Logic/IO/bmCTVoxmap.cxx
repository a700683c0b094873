#include "bmCTVoxmap.h"

#include <nlohmann/json.hpp>

#include "bmCTReader.h"
#include "bmImport.h"

#include <itkImageFileWriter.h>
#include <itkMetaImageIO.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bm {

namespace {

CTImage ToCTImage(const CTVolumeView& v) {
  for (int a = 0; a < 3; ++a) {
    if (v.dims[a] < 1)
      throw std::runtime_error(v.source + ": the volume is empty (" + std::to_string(v.dims[0]) +
                               " x " + std::to_string(v.dims[1]) + " x " +
                               std::to_string(v.dims[2]) + " voxels)");
    if (!(v.spacing[a] > 0) || !std::isfinite(v.spacing[a]))
      throw std::runtime_error(v.source + ": the voxel spacing must be > 0 mm along each axis");
  }
  if (!v.values)
    throw std::runtime_error(v.source + ": the volume has no values");
  CTImage ct;
  ct.hu = HUImage::New();
  HUImage::RegionType region;
  region.SetSize({{size_t(v.dims[0]), size_t(v.dims[1]), size_t(v.dims[2])}});
  ct.hu->SetRegions(region);
  ct.hu->SetSpacing(v.spacing.data());
  ct.hu->SetOrigin(v.origin.data());
  HUImage::DirectionType d;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      d[r][c] = v.direction[size_t(3 * r + c)];
  ct.hu->SetDirection(d);
  ct.hu->Allocate();
  const size_t n = size_t(v.dims[0]) * size_t(v.dims[1]) * size_t(v.dims[2]);
  std::copy(v.values, v.values + n, ct.hu->GetBufferPointer());
  const auto [lo, hi] = std::minmax_element(v.values, v.values + n);
  ct.huMin = *lo;
  ct.huMax = *hi;
  ct.source = v.source;
  ct.format = "image data";
  return ct;
}

} // namespace

Voxmap MakeCTVoxmap(const nlohmann::json& ct, const std::string& baseDir, int resolution,
                    const std::function<bool(double, const std::string&)>& progress,
                    bool noFinerThanCT, double toolVoxelMm) {
  nlohmann::json bone = ct;
  if (resolution > 0)
    bone["resolution"] = resolution;
  if (noFinerThanCT)
    bone["noFinerThanCT"] = true;
  if (noFinerThanCT && toolVoxelMm > 0)
    bone["toolVoxelMm"] = toolVoxelMm;
  return VoxmapFromScene(bone, baseDir, progress ? Progress(progress) : Progress());
}

Voxmap MakeCTVoxmapFromVolume(const CTVolumeView& volume, const nlohmann::json& options,
                              int resolution,
                              const std::function<bool(double, const std::string&)>& progress,
                              std::string* report) {
  ImportOptions opt = ImportOptionsFromJson(options);
  if (resolution > 0)
    opt.resolution = resolution;
  CTImage ct = ToCTImage(volume);
  IntensityEvidence evidence;
  evidence.file = volume.source;
  evidence.format = ct.format;
  evidence.storedBits = volume.storedBits;
  evidence.storedInteger = volume.storedInteger;
  ApplyIntensityDecision(ct, evidence, opt.read.intensity);
  ImportResult r = ImportVoxmap(std::move(ct), opt, progress ? Progress(progress) : Progress());
  if (report)
    *report = r.Report();
  return std::move(r.voxmap);
}

void SaveCTVolume(const CTVolumeView& volume, const std::string& path) {
  CTImage ct = ToCTImage(volume);
  auto writer = itk::ImageFileWriter<HUImage>::New();
  writer->SetInput(ct.hu);
  writer->SetImageIO(itk::MetaImageIO::New());
  writer->SetFileName(path);
  writer->SetUseCompression(false);
  RunFilter(writer, Progress(), "writing the CT to " + path);
}

} // namespace bm
