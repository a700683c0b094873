#include "bmImport.h"

#include "bmAtomicFile.h"

#include "bmHeaderCheck.h"
#include "bmPhantom.h"
#include "bmVoxmapFile.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <unistd.h>

#include <filesystem>
#include <iomanip>
#include <sstream>

namespace fs = std::filesystem;

namespace bm {

namespace {

std::string Box(const Box3& b) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(2) << "[" << b.lo[0] << ", " << b.hi[0] << "] x ["
     << b.lo[1] << ", " << b.hi[1] << "] x [" << b.lo[2] << ", " << b.hi[2] << "] mm";
  return os.str();
}

/// The segmentation's bone volume (mm^3) inside a world box: each CT voxel's fraction times the
/// part of its cell inside the box (exact for a CT on the world axes; for an oblique CT, whole
/// voxels by their centres). The CT is cropped to the box plus a margin, which this leaves out.
double VolumeInBox(const BoneSegmentation& seg, const Box3& box) {
  const FractionImage* f = seg.fraction.GetPointer();
  const auto region = f->GetLargestPossibleRegion();
  const auto sp = f->GetSpacing();
  bool axisAligned = true;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      axisAligned &= std::abs(f->GetDirection()[r][c] - (r == c ? 1.0 : 0.0)) < 1e-9;
  const float* F = f->GetBufferPointer();
  long double sum = 0;
  FractionImage::IndexType index;
  itk::Point<double, 3> p;
  int64_t v = 0;
  for (size_t k = 0; k < region.GetSize(2); ++k)
    for (size_t j = 0; j < region.GetSize(1); ++j)
      for (size_t i = 0; i < region.GetSize(0); ++i, ++v) {
        if (F[v] <= 0)
          continue;
        index[0] = region.GetIndex(0) + long(i);
        index[1] = region.GetIndex(1) + long(j);
        index[2] = region.GetIndex(2) + long(k);
        f->TransformIndexToPhysicalPoint(index, p);
        double share = 1;
        for (int a = 0; a < 3; ++a) {
          if (axisAligned) {
            const double lo = std::max(p[a] - 0.5 * sp[a], box.lo[a]);
            const double hi = std::min(p[a] + 0.5 * sp[a], box.hi[a]);
            share *= std::max(0.0, hi - lo) / sp[a];
          } else if (p[a] < box.lo[a] || p[a] > box.hi[a]) {
            share = 0;
          }
        }
        sum += share * F[v];
      }
  return double(sum) * sp[0] * sp[1] * sp[2];
}

bool Inside(const Box3& b, const std::array<double, 3>& p) {
  for (int a = 0; a < 3; ++a)
    if (p[a] < b.lo[a] || p[a] > b.hi[a])
      return false;
  return true;
}

} // namespace

/// Segmentation working memory per CT voxel, bytes: mask, two label images, fraction, bone HU,
/// band.
constexpr uint64_t kSegmentationBytesPerVoxel = 18;

void CheckVoxmapOutputPath(const std::string& output) {
  std::string ext = fs::path(output).extension().string();
  for (auto& c : ext)
    c = char(std::tolower((unsigned char)c));
  if (ext != ".nrrd" && ext != ".mha")
    throw std::runtime_error("output '" + output + "' must end in .nrrd or .mha");
  fs::path dir = fs::path(output).parent_path();
  if (!dir.empty() && !fs::is_directory(dir))
    throw std::runtime_error("output folder '" + dir.string() + "' does not exist");
  if (fs::is_directory(output))
    throw std::runtime_error("output '" + output + "' is a folder");
  // The save goes through a temporary beside it (".NAME.tmp-PID-N.EXT"): a name that the file
  // system takes but its temporary's does not would fail after the whole import.
  const std::string temporary = fs::path(TemporarySibling(output)).filename().string();
  const long nameMax = ::pathconf(dir.empty() ? "." : dir.c_str(), _PC_NAME_MAX);
  if (nameMax > 0 && long(temporary.size()) > nameMax)
    throw std::runtime_error(
        "output '" + output + "': its name is " +
        std::to_string(fs::path(output).filename().string().size()) +
        " characters long; with its temporary's " +
        std::to_string(temporary.size() - fs::path(output).filename().string().size()) +
        " more it exceeds the file system's limit of " + std::to_string(nameMax) +
        " (choose a shorter name)");
}

ImportResult ImportVoxmap(const std::string& input, const ImportOptions& opt,
                          const Progress& progress) {
  // Without a region the whole CT is segmented: a CT whose segmentation cannot fit is refused
  // from its header, before it is read (the same need as the check before segmenting).
  ReadOptions read = opt.read;
  if (!opt.roiMm && !opt.segmentation.box)
    read.extraBytesPerVoxel = kSegmentationBytesPerVoxel;
  CTImage ct = ReadCT(input, read, progress.Range(0, 0.35));
  return ImportVoxmap(std::move(ct), opt, progress.Range(0.35, 1));
}

ImportResult ImportVoxmap(CTImage ct, const ImportOptions& optIn, const Progress& progress) {
  ImportOptions opt = optIn; // raw values set the threshold and a uniform material
  AdjustForIntensity(ct.intensity, opt.segmentation, opt.material);
  if (opt.resolution < 8 || opt.resolution > 8192)
    throw std::runtime_error("resolution " + std::to_string(opt.resolution) +
                             " is out of range (8 .. 8192 cells)");
  ImportResult r;
  r.source = ct.source;
  r.format = ct.format;
  r.modality = ct.modality;
  r.seriesUID = ct.seriesUID;
  r.seriesDescription = ct.seriesDescription;
  r.transferSyntax = ct.transferSyntax;
  r.numFiles = ct.numFiles;
  r.ctSize = ct.Size();
  r.ctSpacing = ct.Spacing();
  r.ctBounds = ct.WorldBounds();
  r.huMin = ct.huMin;
  r.huMax = ct.huMax;
  r.warnings = ct.warnings;
  r.notes = ct.notes;
  r.intensity = ct.intensity;

  const auto& seed = opt.segmentation.seedMm;
  if (seed && !Inside(r.ctBounds, *seed)) {
    std::ostringstream os;
    os << "the seed point (" << (*seed)[0] << ", " << (*seed)[1] << ", " << (*seed)[2]
       << ") mm lies outside the image, whose bounds are " << Box(r.ctBounds);
    throw std::runtime_error(os.str());
  }
  if (opt.roiMm) {
    for (int a = 0; a < 3; ++a)
      if (!(opt.roiMm->hi[a] > opt.roiMm->lo[a]))
        throw std::runtime_error("the region of interest " + Box(*opt.roiMm) +
                                 " is empty along an axis");
    if (!opt.roiMm->Intersects(r.ctBounds))
      throw std::runtime_error("the region of interest " + Box(*opt.roiMm) +
                               " lies outside the CT, whose bounds are " + Box(r.ctBounds));
    if (seed && !Inside(*opt.roiMm, *seed))
      throw std::runtime_error("the seed point lies outside the region of interest " +
                               Box(*opt.roiMm));
    ct = CropCT(ct, *opt.roiMm, 2);
  }
  if (const auto& box = opt.segmentation.box) {
    box->Check("the oriented box");
    const Box3 bounds = box->Bounds();
    if (!bounds.Intersects(r.ctBounds))
      throw std::runtime_error("the oriented box (bounds " + Box(bounds) +
                               ") lies outside the CT, whose bounds are " + Box(r.ctBounds));
    if (seed && !box->Contains(*seed))
      throw std::runtime_error("the seed point lies outside the oriented box");
    ct = CropCT(ct, bounds, 2);
  }
  // Segmentation working memory: mask, two label images, fraction, bone HU, band (per CT voxel).
  const uint64_t ctVoxels = uint64_t(ct.hu->GetLargestPossibleRegion().GetNumberOfPixels());
  CheckMemoryBudget(ct.Bytes() + ctVoxels * kSegmentationBytesPerVoxel, opt.read.maxMemoryBytes,
                    "segmenting the CT");

  BoneSegmentation seg = SegmentBone(ct, opt.segmentation, progress.Range(0, 0.5));
  ct.hu = nullptr; // release the HU voxels
  r.segmentedVolumeMm3 = opt.roiMm ? VolumeInBox(seg, *opt.roiMm) : seg.boneVolumeMm3;
  {
    const auto sp = seg.fraction->GetSpacing();
    r.thresholdVolumeMm3 = double(seg.thresholdVoxels) * sp[0] * sp[1] * sp[2];
  }
  r.numComponents = seg.numComponents;
  r.holesFilled = seg.holesFilled;
  r.separationDepthMm = seg.separation.depthMm;
  r.warnings.insert(r.warnings.end(), seg.warnings.begin(), seg.warnings.end());
  if (!opt.segmentation.excludeHeads.empty()) {
    const auto sp = seg.fraction->GetSpacing();
    std::ostringstream note;
    note << std::fixed << std::setprecision(1) << double(seg.headVoxels) * sp[0] * sp[1] * sp[2]
         << " mm^3 of bone of the humeral head cut off its glenoid left out (head";
    for (const auto& h : opt.segmentation.excludeHeads)
      note << " (" << h.centreMm[0] << ", " << h.centreMm[1] << ", " << h.centreMm[2]
           << ") mm, radius " << h.radiusMm << " mm";
    note << ")";
    r.notes.push_back(note.str());
  }
  if (opt.roiMm) {
    r.roi = *opt.roiMm;
  } else {
    // The bone's voxels and the half CT voxel the resampler's interpolation reaches beyond them.
    const auto sp = seg.fraction->GetSpacing();
    const double grow = 0.5 * std::max({sp[0], sp[1], sp[2]});
    const Box3 ctBox =
        WorldBoxOfRegion(seg.fraction.GetPointer(), seg.fraction->GetLargestPossibleRegion());
    r.roi = seg.boneBounds;
    for (int a = 0; a < 3; ++a) {
      r.roi.lo[a] = std::max(r.roi.lo[a] - grow, ctBox.lo[a]);
      r.roi.hi[a] = std::min(r.roi.hi[a] + grow, ctBox.hi[a]);
    }
  }

  int resolution = opt.resolution;
  if (opt.noFinerThanCT) {
    const double ct = std::min({r.ctSpacing[0], r.ctSpacing[1], r.ctSpacing[2]});
    const double finest = opt.toolVoxelMm > 0 ? std::min(ct, opt.toolVoxelMm) : ct;
    const double longest =
        std::max({r.roi.hi[0] - r.roi.lo[0], r.roi.hi[1] - r.roi.lo[1], r.roi.hi[2] - r.roi.lo[2]});
    if (const int cells = CellsNoFinerThan(longest, finest); cells > 0 && cells < resolution) {
      resolution = cells;
      std::ostringstream note;
      note << std::setprecision(4) << "voxmap at " << cells << " cells along " << longest
           << " mm: no finer than the CT's " << ct << " mm spacing";
      if (finest < ct)
        note << " or than the tool needs (" << finest << " mm)";
      r.notes.push_back(note.str());
    }
  }
  VoxmapGrid grid = GridForBox(r.roi, resolution);
  const uint64_t segBytes = ctVoxels * 2 * sizeof(float);
  // The voxmap, plus a same-size copy when it is saved.
  CheckMemoryBudget(segBytes + 2 * VoxmapBytes(grid), opt.read.maxMemoryBytes,
                    "the voxmap (" + std::to_string(grid.dims[0]) + " x " +
                        std::to_string(grid.dims[1]) + " x " + std::to_string(grid.dims[2]) +
                        " voxels)");
  r.voxmap = ResampleToVoxmap(seg, grid, opt.material, progress.Range(0.5, 1), opt.threads);
  if (r.voxmap.CountBone() == 0)
    throw std::runtime_error("no bone inside the region of interest " + Box(r.roi) +
                             " at threshold " + std::to_string(int(opt.segmentation.thresholdHU)) +
                             " " + opt.segmentation.valueUnit);
  return r;
}

ImportResult ImportToFile(const std::string& input, const std::string& output,
                          const ImportOptions& opt, const Progress& progress) {
  CheckVoxmapOutputPath(output);
  CheckOutputIsNotInput(input, output);
  ImportResult r = ImportVoxmap(input, opt, progress.Range(0, 0.9));
  SaveVoxmap(r.voxmap, output, progress.Range(0.9, 1),
             {{"bm_intensity_mapping", r.intensity.Key()},
              {"bm_intensity", r.intensity.Describe()},
              {"bm_material_calibrated", r.intensity.materialCalibrated ? "true" : "false"}});
  return r;
}

std::string ImportResult::Report() const {
  std::ostringstream os;
  os << std::fixed;
  os << "read:        " << source << " (" << format;
  if (numFiles > 1)
    os << ", " << numFiles << " files";
  os << ")\n";
  os << "modality:    " << (modality.empty() ? "not stated" : modality) << "\n";
  if (!seriesUID.empty())
    os << "series:      " << seriesUID
       << (seriesDescription.empty() ? "" : " \"" + seriesDescription + "\"") << "\n";
  if (!transferSyntax.empty())
    os << "encoding:    " << transferSyntax << "\n";
  os << "size:        " << ctSize[0] << " x " << ctSize[1] << " x " << ctSize[2] << " voxels\n";
  os << std::setprecision(4) << "spacing:     " << ctSpacing[0] << " x " << ctSpacing[1] << " x "
     << ctSpacing[2] << " mm\n";
  os << "bounds:      " << Box(ctBounds) << "\n";
  if (intensity.kind == IntensityKind::Raw)
    os << std::setprecision(0) << "values:      " << huMin << " .. " << huMax
       << " (as stored, not HU)\n";
  else
    os << std::setprecision(0) << "HU range:    " << huMin << " .. " << huMax << " HU\n";
  os << "intensity:   " << intensity.Describe() << "\n";
  os << std::setprecision(1) << "threshold:   " << thresholdVolumeMm3
     << " mm^3 of voxels at or above the threshold (every bone in the region)\n";
  os << std::setprecision(1) << "bone (CT):   " << segmentedVolumeMm3 << " mm^3";
  if (numComponents > 0)
    os << " (1 of " << numComponents << " components kept";
  if (numComponents > 0)
    os << ", " << holesFilled << " holes filled)";
  os << "\n";
  if (separationDepthMm > 0)
    os << std::setprecision(1) << "separated:   from the bones at the exclude seeds (erosion "
       << separationDepthMm << " mm)\n";
  const auto& d = voxmap.Dims();
  os << std::setprecision(4) << "voxmap:      " << d[0] << " x " << d[1] << " x " << d[2]
     << " voxels of " << voxmap.Spacing() << " mm over " << Box(roi) << "\n";
  os << std::setprecision(1) << "bone volume: " << voxmap.BoneVolume() << " mm^3 ("
     << voxmap.CountBone() << " voxels with bone)\n";
  for (const auto& n : notes)
    os << "note:        " << n << "\n";
  for (const auto& w : warnings)
    os << "warning:     " << w << "\n";
  return os.str();
}

Box3 RoiFromCorners(const std::vector<double>& c, const std::string& what) {
  if (c.size() != 6)
    throw std::runtime_error(what + " must hold 6 numbers: x0, y0, z0, x1, y1, z1 (mm)");
  Box3 b;
  static const char* axis[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(c[size_t(a)]) || !std::isfinite(c[size_t(a) + 3]))
      throw std::runtime_error(what + " holds a value that is not a finite number");
    b.lo[a] = c[size_t(a)];
    b.hi[a] = c[size_t(a) + 3];
    if (!(b.hi[a] > b.lo[a])) {
      std::ostringstream os;
      os << what << " is inverted or empty along " << axis[a] << ": " << axis[a]
         << "1 = " << b.hi[a] << " mm is not above " << axis[a] << "0 = " << b.lo[a]
         << " mm (the order is x0, y0, z0, x1, y1, z1)";
      throw std::runtime_error(os.str());
    }
  }
  return b;
}

std::vector<std::array<double, 3>> ParsePointsMm(const std::string& text, const std::string& what) {
  std::string t = text;
  for (char& ch : t)
    if (ch == ',' || ch == ';')
      ch = ' ';
  std::istringstream is(t);
  std::vector<double> v;
  std::string word;
  while (is >> word) {
    char* end = nullptr;
    const double x = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end || !std::isfinite(x))
      throw std::runtime_error(what + ": '" + word + "' is not a number");
    v.push_back(x);
  }
  if (v.empty() || v.size() % 3)
    throw std::runtime_error(what + " must be points x,y,z (mm), several separated by ';'");
  std::vector<std::array<double, 3>> out;
  for (size_t i = 0; i < v.size(); i += 3)
    out.push_back({v[i], v[i + 1], v[i + 2]});
  return out;
}

OrientedBox OrientedBoxFromText(const std::string& text, const std::string& what) {
  const auto p = ParsePointsMm(text, what);
  if (p.size() != 2 && p.size() != 3)
    throw std::runtime_error(what + " must be CX,CY,CZ,HX,HY,HZ[,RX,RY,RZ] (centre and half "
                                    "sizes in mm, rotation in degrees)");
  OrientedBox box;
  box.centreMm = p[0];
  box.halfSizesMm = p[1];
  if (p.size() == 3)
    box.rotationDeg = p[2];
  box.Check(what);
  return box;
}

ImportOptions ImportOptionsFromJson(const nlohmann::json& j) {
  ImportOptions o;
  auto num = [&](const char* key) {
    if (!j.at(key).is_number())
      throw std::runtime_error(std::string("bone: '") + key + "' must be a number");
    return j.at(key).get<double>();
  };
  auto flag = [&](const char* key) {
    if (!j.at(key).is_boolean())
      throw std::runtime_error(std::string("bone: '") + key + "' must be true or false");
    return j.at(key).get<bool>();
  };
  auto vec = [&](const char* key, size_t n) {
    const auto& v = j.at(key);
    if (!v.is_array() || v.size() != n)
      throw std::runtime_error(std::string("bone: '") + key + "' must be an array of " +
                               std::to_string(n) + " numbers");
    std::vector<double> out;
    for (const auto& x : v) {
      if (!x.is_number())
        throw std::runtime_error(std::string("bone: '") + key + "' must hold numbers");
      out.push_back(x.get<double>());
    }
    return out;
  };
  if (!j.is_object())
    throw std::runtime_error("bone: expected an object");
  if (j.contains("threshold"))
    o.segmentation.thresholdHU = float(num("threshold"));
  if (j.contains("seed")) {
    auto s = vec("seed", 3);
    o.segmentation.seedMm = std::array<double, 3>{s[0], s[1], s[2]};
  }
  if (j.contains("roi"))
    o.roiMm = RoiFromCorners(vec("roi", 6), "bone: 'roi'");
  if (j.contains("exclude")) {
    const auto& e = j["exclude"];
    if (!e.is_array())
      throw std::runtime_error("bone: 'exclude' must be an array of [x, y, z] points (mm)");
    for (const auto& p : e) {
      if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
          !p[2].is_number())
        throw std::runtime_error("bone: 'exclude' must be an array of [x, y, z] points (mm)");
      o.segmentation.excludeSeedsMm.push_back(
          {p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
    }
  }
  if (j.contains("exclude_heads")) {
    const auto& e = j["exclude_heads"];
    if (!e.is_array())
      throw std::runtime_error("bone: 'exclude_heads' must be an array of heads");
    for (const auto& b : e)
      o.segmentation.excludeHeads.push_back(ExcludedHeadFromJson(b, "bone: 'exclude_heads'"));
  }
  if (j.contains("box")) {
    const auto& b = j["box"];
    if (!b.is_object() || !b.contains("centre") || !b.contains("halfSizes"))
      throw std::runtime_error("bone: 'box' must be {\"centre\": [x, y, z] mm, \"halfSizes\": "
                               "[a, b, c] mm, \"rotation\": [rx, ry, rz] deg}");
    OrientedBox box;
    auto three = [&](const char* key, std::array<double, 3>& out) {
      const auto& v = b.at(key);
      if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
          !v[2].is_number())
        throw std::runtime_error(std::string("bone: 'box' '") + key + "' must be 3 numbers");
      for (int a = 0; a < 3; ++a)
        out[size_t(a)] = v[size_t(a)].get<double>();
    };
    three("centre", box.centreMm);
    three("halfSizes", box.halfSizesMm);
    if (b.contains("rotation"))
      three("rotation", box.rotationDeg);
    box.Check("bone: 'box'");
    o.segmentation.box = box;
  }
  if (j.contains("closingRadius")) {
    const double c = num("closingRadius");
    if (c != std::floor(c) || c < 0 || c > 10)
      throw std::runtime_error("bone: 'closingRadius' must be an integer 0 .. 10 (voxels)");
    o.segmentation.closingRadiusVoxels = int(c);
  }
  if (j.contains("separationDepth")) {
    o.segmentation.separation.maxDepthMm = num("separationDepth");
    if (!(o.segmentation.separation.maxDepthMm > 0))
      throw std::runtime_error("bone: 'separationDepth' must be > 0 mm");
  }
  if (j.contains("resolution")) {
    double n = num("resolution");
    if (n != std::floor(n) || n < 8 || n > 8192)
      throw std::runtime_error("bone: 'resolution' must be an integer 8 .. 8192");
    o.resolution = int(n);
  }
  if (j.contains("series")) {
    if (!j["series"].is_string())
      throw std::runtime_error("bone: 'series' must be a SeriesInstanceUID string");
    o.read.seriesUID = j["series"].get<std::string>();
  }
  if (j.contains("keepAllComponents"))
    o.segmentation.keepAllComponents = flag("keepAllComponents");
  if (j.contains("noFinerThanCT"))
    o.noFinerThanCT = flag("noFinerThanCT");
  if (j.contains("toolVoxelMm")) {
    o.toolVoxelMm = num("toolVoxelMm");
    if (!(o.toolVoxelMm > 0) || !std::isfinite(o.toolVoxelMm))
      throw std::runtime_error("bone: 'toolVoxelMm' must be > 0 mm");
  }
  if (j.contains("fillHoles"))
    o.segmentation.fillHoles = flag("fillHoles");
  if (j.contains("maxHoleVolume"))
    o.segmentation.maxHoleVolumeMm3 = num("maxHoleVolume");
  if (j.contains("maxMemoryMB"))
    o.read.maxMemoryBytes = uint64_t(num("maxMemoryMB") * 1048576.0);
  if (j.contains("corticalHU"))
    o.material.corticalHU = float(num("corticalHU"));
  // How to read values that are not HU (Docs/CTImport.md, "Intensities").
  if (j.contains("rawThreshold")) {
    if (j.contains("threshold"))
      throw std::runtime_error("bone: give 'threshold' (HU) or 'rawThreshold' (the file's units), "
                               "not both");
    o.read.intensity.rawThreshold = num("rawThreshold");
  }
  if (j.contains("huMapping")) {
    const auto m = vec("huMapping", 2);
    o.read.intensity.huMapping = std::array<double, 2>{m[0], m[1]};
  }
  if (j.contains("allowOutsideData"))
    o.read.allowDataOutsideFolder = flag("allowOutsideData");
  return o;
}

nlohmann::json ImportOptionsToJson(const ImportOptions& o) {
  nlohmann::json j = nlohmann::json::object();
  const auto& seg = o.segmentation;
  const auto& in = o.read.intensity;
  if (in.rawThreshold)
    j["rawThreshold"] = *in.rawThreshold;
  else
    j["threshold"] = seg.thresholdHU;
  if (in.huMapping)
    j["huMapping"] = *in.huMapping;
  if (!o.read.seriesUID.empty())
    j["series"] = o.read.seriesUID;
  if (seg.seedMm)
    j["seed"] = *seg.seedMm;
  if (!seg.excludeSeedsMm.empty())
    j["exclude"] = seg.excludeSeedsMm;
  if (!seg.excludeHeads.empty()) {
    j["exclude_heads"] = nlohmann::json::array();
    for (const auto& h : seg.excludeHeads)
      j["exclude_heads"].push_back(ExcludedHeadToJson(h));
  }
  if (o.roiMm)
    j["roi"] = {o.roiMm->lo[0], o.roiMm->lo[1], o.roiMm->lo[2],
                o.roiMm->hi[0], o.roiMm->hi[1], o.roiMm->hi[2]};
  if (seg.box)
    j["box"] = {{"centre", seg.box->centreMm},
                {"halfSizes", seg.box->halfSizesMm},
                {"rotation", seg.box->rotationDeg}};
  j["keepAllComponents"] = seg.keepAllComponents;
  j["fillHoles"] = seg.fillHoles;
  j["resolution"] = o.resolution;
  if (o.read.allowDataOutsideFolder)
    j["allowOutsideData"] = true;
  if (o.read.maxMemoryBytes > 0)
    j["maxMemoryMB"] = double(o.read.maxMemoryBytes) / 1048576.0;
  return j;
}

Voxmap VoxmapFromScene(const nlohmann::json& bone, const std::string& baseDir,
                       const Progress& progress) {
  if (!bone.is_object())
    throw std::runtime_error("bone: expected an object");
  int sources =
      int(bone.contains("voxmap")) + int(bone.contains("ct")) + int(bone.contains("phantom"));
  if (sources != 1)
    throw std::runtime_error("bone: name exactly one of 'voxmap', 'ct' or 'phantom'");
  auto resolve = [&](const std::string& key) {
    if (!bone[key].is_string())
      throw std::runtime_error("bone: '" + key + "' must be a path string");
    fs::path p(bone[key].get<std::string>());
    return (p.is_absolute() || baseDir.empty() ? p : fs::path(baseDir) / p).string();
  };
  if (bone.contains("voxmap"))
    return LoadVoxmap(resolve("voxmap"), progress);
  ImportOptions opt = ImportOptionsFromJson(bone);
  if (bone.contains("ct"))
    return ImportVoxmap(resolve("ct"), opt, progress).voxmap;
  if (!bone["phantom"].is_string())
    throw std::runtime_error("bone: 'phantom' must be glenoid, block or shoulder");
  std::string name = bone["phantom"].get<std::string>();
  CTImage ct = MakePhantomCT(name, {}, progress.Range(0, 0.3));
  return ImportVoxmap(std::move(ct), opt, progress.Range(0.3, 1)).voxmap;
}

} // namespace bm
