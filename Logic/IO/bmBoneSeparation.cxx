#include "bmBoneSeparation.h"

#include <itkBinaryThresholdImageFilter.h>
#include <itkMorphologicalWatershedFromMarkersImageFilter.h>
#include <itkSignedMaurerDistanceMapImageFilter.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace bm {

namespace {
using DistanceImage = itk::Image<float, 3>;

std::string FormatIndex(const std::array<int, 3>& v) {
  std::ostringstream os;
  os << "voxel (" << v[0] << ", " << v[1] << ", " << v[2] << ")";
  return os.str();
}
} // namespace

SeparationResult SeparateBones(MaskImage* mask, const std::optional<std::array<int, 3>>& include,
                               const std::vector<std::array<int, 3>>& exclude,
                               const SeparationOptions& opt, const Progress& progress) {
  SeparationResult res;
  if (exclude.empty())
    return res;
  if (!(opt.maxDepthMm > 0))
    throw std::runtime_error("the bone separation depth must be > 0 mm");
  const auto region = mask->GetLargestPossibleRegion();
  const int64_t n = int64_t(region.GetNumberOfPixels());
  uint8_t* M = mask->GetBufferPointer();
  const int nx = int(region.GetSize(0)), ny = int(region.GetSize(1));
  auto at = [&](const std::array<int, 3>& v) {
    return int64_t(v[0]) + int64_t(nx) * (int64_t(v[1]) + int64_t(ny) * v[2]);
  };
  if (include && !M[at(*include)])
    throw std::runtime_error("the include seed's " + FormatIndex(*include) + " is not bone");
  for (const auto& e : exclude)
    if (!M[at(e)])
      throw std::runtime_error("the exclude seed's " + FormatIndex(e) + " is not bone");

  // 1. Depth below the surface, mm (positive inside).
  auto binary = MaskImage::New();
  binary->CopyInformation(mask);
  binary->SetRegions(region);
  binary->Allocate();
  uint8_t* B = binary->GetBufferPointer();
  for (int64_t v = 0; v < n; ++v)
    B[v] = M[v] ? 1 : 0;
  auto distance = itk::SignedMaurerDistanceMapImageFilter<MaskImage, DistanceImage>::New();
  distance->SetInput(binary);
  distance->SetInsideIsPositive(true);
  distance->SetSquaredDistance(false);
  distance->SetUseImageSpacing(true);
  distance->SetBackgroundValue(0);
  RunFilter(distance, progress.Range(0, 0.2), "separating bones: distance map");
  DistanceImage::Pointer depth = distance->GetOutput();
  depth->DisconnectPipeline();

  // 2. Erode deeper until the seeds' cores fall apart.
  const auto sp = mask->GetSpacing();
  const double step = std::min({sp[0], sp[1], sp[2]});
  const int steps = std::max(1, int(std::floor(opt.maxDepthMm / step + 1e-9)));
  LabelImage::Pointer cores;
  uint32_t keepLabel = 0;
  std::vector<uint32_t> dropLabels;
  for (int s = 1; s <= steps && !cores; ++s) {
    const double d = s * step;
    const Progress p = progress.Range(0.2 + 0.5 * (s - 1) / steps, 0.2 + 0.5 * s / steps);
    auto thr = itk::BinaryThresholdImageFilter<DistanceImage, MaskImage>::New();
    thr->SetInput(depth);
    thr->SetLowerThreshold(float(d));
    thr->SetUpperThreshold(std::numeric_limits<float>::max());
    thr->SetInsideValue(1);
    thr->SetOutsideValue(0);
    RunFilter(thr, p.Range(0, 0.3), "separating bones: erosion");
    std::vector<itk::SizeValueType> sizes;
    LabelImage::Pointer labels =
        LabelComponents(thr->GetOutput(), false, sizes, p.Range(0.3, 1), "separating bones");
    const int radius = int(std::ceil(d / step)) + 1;
    auto core = [&](const std::array<int, 3>& v, const char* what) {
      const uint32_t l = NearestLabel(labels, v, radius);
      if (!l) {
        std::ostringstream os;
        os << "cannot separate the bones: the bone at the " << what << " seed's " << FormatIndex(v)
           << " is thinner than " << 2 * d << " mm, and the bones still touch at an erosion of "
           << d - step
           << " mm (move the seed into a thicker part of the bone; an exclude seed on the bone "
              "to keep cannot be separated from it)";
        throw std::runtime_error(os.str());
      }
      return l;
    };
    std::vector<uint32_t> drop;
    for (const auto& e : exclude)
      drop.push_back(core(e, "exclude"));
    uint32_t keep = 0;
    if (include) {
      keep = core(*include, "include");
    } else {
      // The largest core at no exclude seed, once it holds a tenth of the eroded bone (so that
      // a speck split off at a shallow erosion is not taken for the bone).
      itk::SizeValueType total = 0;
      for (auto z : sizes)
        total += z;
      for (uint32_t l = 1; l <= sizes.size() && !keep; ++l) // largest first
        if (std::find(drop.begin(), drop.end(), l) == drop.end() && sizes[l - 1] * 10 >= total)
          keep = l;
    }
    if (keep && std::find(drop.begin(), drop.end(), keep) == drop.end()) {
      cores = labels;
      keepLabel = keep;
      dropLabels = drop;
      res.depthMm = d;
      res.regions = int(sizes.size());
    }
  }
  if (!cores) {
    std::ostringstream os;
    os << "cannot separate the bones: the bone to keep and the bone at an exclude seed stay "
          "joined down to an erosion of "
       << steps * step << " mm (raise the threshold or the separation depth)";
    throw std::runtime_error(os.str());
  }

  // 3. Regrow: flood the negated depth from the cores.
  float* D = depth->GetBufferPointer();
  for (int64_t v = 0; v < n; ++v)
    D[v] = -D[v];
  auto ws = itk::MorphologicalWatershedFromMarkersImageFilter<DistanceImage, LabelImage>::New();
  ws->SetInput(depth);
  ws->SetMarkerImage(cores);
  ws->SetMarkWatershedLine(false);
  ws->SetFullyConnected(false);
  RunFilter(ws, progress.Range(0.7, 0.95), "separating bones: regrowth");
  const uint32_t* W = ws->GetOutput()->GetBufferPointer();

  // 4. Keep the include seed's region.
  for (int64_t v = 0; v < n; ++v) {
    if (!M[v])
      continue;
    if (W[v] == keepLabel) {
      ++res.keptVoxels;
    } else {
      M[v] = 0;
      ++res.droppedVoxels;
    }
  }
  progress(1.0, "separating bones");
  return res;
}

} // namespace bm
