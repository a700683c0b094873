#include "bmMask.h"

#include <itkConnectedComponentImageFilter.h>
#include <itkRelabelComponentImageFilter.h>

#include <cmath>
#include <sstream>

namespace bm {

LabelImage::Pointer LabelComponents(const MaskImage* mask, bool fullyConnected,
                                    std::vector<itk::SizeValueType>& sizes,
                                    const Progress& progress, const std::string& stage) {
  auto cc = itk::ConnectedComponentImageFilter<MaskImage, LabelImage>::New();
  cc->SetInput(mask);
  cc->SetFullyConnected(fullyConnected);
  RunFilter(cc, progress.Range(0, 0.8), stage);
  auto relabel = itk::RelabelComponentImageFilter<LabelImage, LabelImage>::New();
  relabel->SetInput(cc->GetOutput());
  relabel->SetSortByObjectSize(true);
  RunFilter(relabel, progress.Range(0.8, 1), stage);
  sizes = relabel->GetSizeOfObjectsInPixels();
  LabelImage::Pointer out = relabel->GetOutput();
  out->DisconnectPipeline();
  return out;
}

uint32_t NearestLabel(const LabelImage* labels, const std::array<int, 3>& ijk, int radius) {
  const auto region = labels->GetLargestPossibleRegion();
  const int n[3] = {int(region.GetSize(0)), int(region.GetSize(1)), int(region.GetSize(2))};
  const auto sp = labels->GetSpacing();
  const uint32_t* L = labels->GetBufferPointer();
  uint32_t best = 0;
  double bestD = 1e300;
  for (int dk = -radius; dk <= radius; ++dk)
    for (int dj = -radius; dj <= radius; ++dj)
      for (int di = -radius; di <= radius; ++di) {
        const int i = ijk[0] + di, j = ijk[1] + dj, k = ijk[2] + dk;
        if (i < 0 || j < 0 || k < 0 || i >= n[0] || j >= n[1] || k >= n[2])
          continue;
        const uint32_t l = L[i + int64_t(n[0]) * (j + int64_t(n[1]) * k)];
        const double d =
            std::pow(di * sp[0], 2) + std::pow(dj * sp[1], 2) + std::pow(dk * sp[2], 2);
        if (l && d < bestD) {
          bestD = d;
          best = l;
        }
      }
  return best;
}

std::string FormatPointMm(const std::array<double, 3>& p) {
  std::ostringstream os;
  os << "(" << p[0] << ", " << p[1] << ", " << p[2] << ") mm";
  return os.str();
}

} // namespace bm
