#include "bmStoredAxes.h"

#include <itkFlipImageFilter.h>
#include <itkPermuteAxesImageFilter.h>

#include <cctype>
#include <sstream>
#include <stdexcept>

namespace bm {

StoredAxes ParseStoredAxes(const std::string& text) {
  const std::string what = "stored axes '" + text +
                           "': a permutation of x, y and z, each "
                           "optionally prefixed with '-', separated by commas (e.g. x,-z,y)";
  StoredAxes a;
  std::stringstream in(text);
  std::string item;
  std::array<bool, 3> used{false, false, false};
  int n = 0;
  while (std::getline(in, item, ',')) {
    if (n >= 3)
      throw std::invalid_argument(what);
    bool minus = false;
    if (!item.empty() && item[0] == '-')
      minus = true, item.erase(0, 1);
    if (item.size() != 1 || item[0] < 'x' || item[0] > 'z')
      throw std::invalid_argument(what);
    const int w = item[0] - 'x';
    if (used[size_t(w)])
      throw std::invalid_argument(what);
    used[size_t(w)] = true;
    a.world[size_t(n)] = w;
    a.reversed[size_t(n)] = minus;
    ++n;
  }
  if (n != 3)
    throw std::invalid_argument(what);
  return a;
}

CTImage StoreAlongAxes(const CTImage& ct, const StoredAxes& axes) {
  // Permute: stored axis s takes the input's axis world[s] (ITK keeps the world positions by
  // permuting the direction's columns).
  auto permute = itk::PermuteAxesImageFilter<HUImage>::New();
  permute->SetInput(ct.hu);
  itk::FixedArray<unsigned int, 3> order;
  for (unsigned s = 0; s < 3; ++s)
    order[s] = unsigned(axes.world[s]);
  permute->SetOrder(order);
  // Flip: the reversed axes, about the image's own centre; FlipAxes updates origin and direction
  // so the voxels keep their world positions.
  auto flip = itk::FlipImageFilter<HUImage>::New();
  flip->SetInput(permute->GetOutput());
  itk::FixedArray<bool, 3> reversed;
  for (unsigned s = 0; s < 3; ++s)
    reversed[s] = axes.reversed[s];
  flip->SetFlipAxes(reversed);
  flip->FlipAboutOriginOff();
  flip->Update();
  CTImage out = ct;
  out.hu = flip->GetOutput();
  out.hu->DisconnectPipeline();
  return out;
}

} // namespace bm
