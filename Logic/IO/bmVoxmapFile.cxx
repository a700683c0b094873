#include "bmVoxmapFile.h"

#include "bmAtomicFile.h"
#include "bmCTReader.h" // CheckMemoryBudget
#include "bmHeaderCheck.h"

#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>
#include <itkMetaDataObject.h>
#include <itkMetaImageIO.h>
#include <itkNrrdImageIO.h>
#include <itkVectorImage.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace bm {

namespace {

using FileImage = itk::VectorImage<float, 3>;

// Largest material scale accepted in a saved voxmap (1 = cortical bone), as a scene's block
// material (bmScene.cxx): NaN, infinite, huge or negative values would reach the forces.
constexpr float kMaxMaterialScale = 10.0f;

std::string LowerExt(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (auto& c : e)
    c = char(std::tolower((unsigned char)c));
  return e;
}

itk::ImageIOBase::Pointer IOFor(const std::string& path) {
  std::string e = LowerExt(path);
  if (e == ".nrrd")
    return itk::NrrdImageIO::New().GetPointer();
  if (e == ".mha")
    return itk::MetaImageIO::New().GetPointer();
  throw std::runtime_error("'" + path +
                           "': a voxmap is saved as .nrrd or .mha (single-file formats)");
}

std::string Hex(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", v);
  return buf;
}

bool ParseHexTriple(const std::string& s, double out[3]) {
  return std::sscanf(s.c_str(), "%la %la %la", &out[0], &out[1], &out[2]) == 3;
}

std::string HexTriple(const std::array<double, 3>& v) {
  return Hex(v[0]) + " " + Hex(v[1]) + " " + Hex(v[2]);
}

constexpr const char* kTrialEntryField = "bm_trial_entry_mm";
constexpr const char* kTrialAxisField = "bm_trial_axis";
constexpr const char* kTrialToolField = "bm_tool";

} // namespace

void SaveVoxmap(const Voxmap& vm, const std::string& path, const Progress& progress,
                const std::vector<std::pair<std::string, std::string>>& fields) {
  auto io = IOFor(path);
  if (vm.NumVoxels() == 0)
    throw std::runtime_error("cannot save an empty voxmap");
  fs::path target(path);
  fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  if (!fs::is_directory(dir))
    throw std::runtime_error("cannot save '" + path + "': folder '" + dir.string() +
                             "' does not exist");

  auto img = FileImage::New();
  FileImage::RegionType region;
  const auto& d = vm.Dims();
  region.SetSize({{size_t(d[0]), size_t(d[1]), size_t(d[2])}});
  img->SetRegions(region);
  img->SetNumberOfComponentsPerPixel(2);
  FileImage::SpacingType sp;
  FileImage::PointType origin;
  for (int a = 0; a < 3; ++a) {
    sp[a] = vm.Spacing();
    origin[a] = vm.Origin()[a];
  }
  img->SetSpacing(sp);
  img->SetOrigin(origin);
  img->Allocate();
  float* buf = img->GetBufferPointer();
  const Voxmap::Fill* fill = vm.FillData();
  const float* mat = vm.MaterialData();
  const double unit = 1.0 / Voxmap::kFull;
  int64_t v = 0; // the file's voxel, in x-fastest order; the voxmap's rows are padded (Pitch)
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int64_t x = vm.Index(0, j, k), end = x + d[0]; x < end; ++x, ++v) {
        buf[2 * v] = float(double(std::max(fill[x], -Voxmap::kFull)) * unit);
        buf[2 * v + 1] = mat ? mat[x] : 1.0f;
      }
  auto& dict = img->GetMetaDataDictionary();
  itk::EncapsulateMetaData<std::string>(dict, "bm_voxmap_version", "1");
  itk::EncapsulateMetaData<std::string>(dict, "bm_spacing", Hex(vm.Spacing()));
  itk::EncapsulateMetaData<std::string>(dict, "bm_origin",
                                        Hex(vm.Origin()[0]) + " " + Hex(vm.Origin()[1]) + " " +
                                            Hex(vm.Origin()[2]));
  itk::EncapsulateMetaData<std::string>(dict, "bm_components", "bone_fraction material_scale");
  for (const auto& [key, value] : fields)
    itk::EncapsulateMetaData<std::string>(dict, key, value);

  const std::string tmp = TemporarySibling(path);
  auto writer = itk::ImageFileWriter<FileImage>::New();
  writer->SetImageIO(io);
  writer->SetFileName(tmp);
  writer->SetInput(img);
  writer->UseCompressionOn();
  try {
    RunFilter(writer, progress, "saving the voxmap");
    fs::rename(tmp, target);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

namespace {

// A reader of the voxmap file with its header checked and read (not its voxels). Throws
// std::runtime_error naming the file, as LoadVoxmap documents.
itk::ImageFileReader<FileImage>::Pointer OpenVoxmapFile(const std::string& path) {
  if (!fs::exists(path))
    throw std::runtime_error("voxmap file '" + path + "' does not exist");
  auto reader = itk::ImageFileReader<FileImage>::New();
  reader->SetFileName(path);
  std::string e = LowerExt(path);
  // The header is checked before ITK reads anything: ITK's MetaImage reader overflows a buffer on
  // a NRRD named .mha, and a detached data file could name any file or a device.
  HeaderLimits limits;
  limits.maxComponents = 2;
  if (e == ".nrrd" || e == ".nhdr") {
    CheckVolumeHeader(path, "NRRD", limits);
    reader->SetImageIO(itk::NrrdImageIO::New());
  } else if (e == ".mha" || e == ".mhd") {
    CheckVolumeHeader(path, "MetaImage", limits);
    reader->SetImageIO(itk::MetaImageIO::New());
  } else {
    throw std::runtime_error("voxmap file '" + path + "': a voxmap is .nrrd, .nhdr, .mha or .mhd");
  }
  // What ITK itself will allocate, from the header it parsed, before it allocates: the header
  // check's reading of a malformed header can differ from ITK's (a fuzzed MetaImage made ITK ask
  // for 64 GiB).
  try {
    reader->UpdateOutputInformation();
  } catch (const std::exception& ex) {
    throw std::runtime_error("voxmap file '" + path + "': cannot read its header: " + ex.what());
  }
  {
    const FileImage* info = reader->GetOutput();
    const long double bytes = (long double)info->GetLargestPossibleRegion().GetNumberOfPixels() *
                              std::max(1u, info->GetNumberOfComponentsPerPixel()) * sizeof(float);
    CheckMemoryBudget(bytes > 1e18L ? uint64_t(1e18) : uint64_t(bytes), limits.maxMemoryBytes,
                      "the voxmap file '" + path + "'");
  }
  return reader;
}

} // namespace

Voxmap LoadVoxmap(const std::string& path, const Progress& progress) {
  auto reader = OpenVoxmapFile(path);
  RunFilter(reader, progress.Range(0, 0.8), "loading the voxmap");
  FileImage::Pointer img = reader->GetOutput();
  const unsigned nc = img->GetNumberOfComponentsPerPixel();
  if (nc < 1 || nc > 2)
    throw std::runtime_error(
        "'" + path + "' has " + std::to_string(nc) +
        " components per voxel; a voxmap has 2 (bone fraction, material) or 1");
  const auto& dir = img->GetDirection();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (std::abs(dir[r][c] - (r == c ? 1.0 : 0.0)) > 1e-9)
        throw std::runtime_error("'" + path +
                                 "' is not aligned with the world axes; a voxmap must be");
  auto sp = img->GetSpacing();
  auto org = img->GetOrigin();
  double spacing = sp[0];
  double origin[3] = {org[0], org[1], org[2]};
  for (int a = 1; a < 3; ++a)
    if (std::abs(sp[a] - sp[0]) > 1e-9 * sp[0])
      throw std::runtime_error("'" + path +
                               "' has anisotropic spacing; a voxmap's voxels are cubes");
  // Bit-exact geometry from our own fields when they agree with the header.
  const auto& dict = img->GetMetaDataDictionary();
  std::string s;
  double hex[3];
  if (itk::ExposeMetaData<std::string>(dict, "bm_spacing", s) && ParseHexTriple(s + " 0 0", hex) &&
      std::abs(hex[0] - spacing) <= 1e-6 * spacing)
    spacing = hex[0];
  if (itk::ExposeMetaData<std::string>(dict, "bm_origin", s) && ParseHexTriple(s, hex) &&
      std::abs(hex[0] - origin[0]) < 1e-6 && std::abs(hex[1] - origin[1]) < 1e-6 &&
      std::abs(hex[2] - origin[2]) < 1e-6)
    for (int a = 0; a < 3; ++a)
      origin[a] = hex[a];
  const auto size = img->GetLargestPossibleRegion().GetSize();
  Voxmap vm({int(size[0]), int(size[1]), int(size[2])}, spacing, {origin[0], origin[1], origin[2]});
  const float* buf = img->GetBufferPointer();
  Voxmap::Fill* fill = vm.MutableFill();
  int64_t v = 0; // the file's voxel, in x-fastest order; the voxmap's rows are padded (Pitch)
  for (int k = 0; k < int(size[2]); ++k)
    for (int j = 0; j < int(size[1]); ++j)
      for (int64_t x = vm.Index(0, j, k), end = x + int64_t(size[0]); x < end; ++x, ++v) {
        const double f = double(buf[nc * v]);
        if (!std::isfinite(f))
          throw std::runtime_error("'" + path + "' holds a non-finite bone fraction");
        fill[x] = Voxmap::Fill(std::llround(std::clamp(f, -1.0, 1.0) * Voxmap::kFull));
        const float material = nc == 2 ? buf[nc * v + 1] : 1.0f;
        if (!(material >= 0.0f && material <= kMaxMaterialScale)) {
          std::ostringstream m;
          m << "'" << path << "' holds material scale " << material << " at voxel (" << v % size[0]
            << ", " << (v / size[0]) % size[1] << ", " << v / (size[0] * size[1])
            << "); a material scale must be in [0, " << kMaxMaterialScale << "]";
          throw std::runtime_error(m.str());
        }
        if (material != 1.0f)
          vm.SetMaterial(x, material);
      }
  vm.RebuildOccupancy();
  progress(1.0, "loading the voxmap");
  return vm;
}

std::vector<std::pair<std::string, std::string>> VoxmapTrialFields(const VoxmapTrial& trial) {
  std::vector<std::pair<std::string, std::string>> fields = {
      {kTrialEntryField, HexTriple(trial.entryMm)}, {kTrialAxisField, HexTriple(trial.axis)}};
  if (trial.toolJson.find_first_of("\r\n") != std::string::npos)
    throw std::invalid_argument("a voxmap file's tool must be one line of JSON");
  if (!trial.toolJson.empty())
    fields.emplace_back(kTrialToolField, trial.toolJson);
  return fields;
}

std::optional<VoxmapTrial> LoadVoxmapTrial(const std::string& path) {
  auto reader = OpenVoxmapFile(path);
  const auto& dict = reader->GetOutput()->GetMetaDataDictionary();
  std::string entry, axis;
  const bool hasEntry = itk::ExposeMetaData<std::string>(dict, kTrialEntryField, entry);
  const bool hasAxis = itk::ExposeMetaData<std::string>(dict, kTrialAxisField, axis);
  if (!hasEntry && !hasAxis)
    return std::nullopt;
  double e[3], a[3];
  if (!hasEntry || !hasAxis || !ParseHexTriple(entry, e) || !ParseHexTriple(axis, a))
    throw std::runtime_error("voxmap file '" + path + "': its saved trial (" + kTrialEntryField +
                             ", " + kTrialAxisField + ") is incomplete or not three numbers each");
  const double length = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (!std::isfinite(e[0] + e[1] + e[2]) || !std::isfinite(length) || length < 1e-9)
    throw std::runtime_error("voxmap file '" + path +
                             "': its saved trial has a non-finite entry or a zero axis");
  std::string tool;
  itk::ExposeMetaData<std::string>(dict, kTrialToolField, tool);
  return VoxmapTrial{{e[0], e[1], e[2]}, {a[0] / length, a[1] / length, a[2] / length}, tool};
}

} // namespace bm
