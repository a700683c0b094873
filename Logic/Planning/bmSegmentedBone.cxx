#include "bmSegmentedBone.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace bm {

SegmentedBone::SegmentedBone(const Voxmap& vm)
    : Dims_(vm.Dims()), Spacing_(vm.Spacing()), Origin_(vm.Origin()) {
  const int nx = Dims_[0], ny = Dims_[1], nz = Dims_[2];
  const size_t n = size_t(nx) * ny * nz;
  Fraction_.resize(n);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        Fraction_[size_t(Index(i, j, k))] = float(vm.Fraction(vm.Index(i, j, k)));
  // 6-connected components (breadth-first), then relabelled by decreasing size.
  Label_.assign(n, 0);
  std::vector<int64_t> sizes, queue;
  const int64_t step[3] = {1, nx, int64_t(nx) * ny};
  for (size_t s = 0; s < n; ++s) {
    if (Fraction_[s] < 0.5f || Label_[s])
      continue;
    const int label = int(sizes.size()) + 1;
    Label_[s] = label;
    queue.assign(1, int64_t(s));
    for (size_t q = 0; q < queue.size(); ++q) {
      const int64_t v = queue[q];
      const int i = int(v % nx), j = int((v / nx) % ny), k = int(v / (int64_t(nx) * ny));
      const int c[3] = {i, j, k}, lim[3] = {nx, ny, nz};
      for (int a = 0; a < 3; ++a)
        for (int d = -1; d <= 1; d += 2) {
          if (c[a] + d < 0 || c[a] + d >= lim[a])
            continue;
          const int64_t w = v + d * step[a];
          if (Fraction_[size_t(w)] >= 0.5f && !Label_[size_t(w)]) {
            Label_[size_t(w)] = label;
            queue.push_back(w);
          }
        }
    }
    sizes.push_back(int64_t(queue.size()));
  }
  if (sizes.empty())
    throw std::runtime_error("the segmented bone is empty (no voxel is at least half bone)");
  std::vector<int> order(sizes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return sizes[a] > sizes[b]; });
  std::vector<int> relabel(sizes.size() + 1, 0);
  Sizes_.resize(sizes.size());
  for (size_t r = 0; r < order.size(); ++r) {
    relabel[size_t(order[r]) + 1] = int(r) + 1;
    Sizes_[r] = sizes[size_t(order[r])];
  }
  for (auto& l : Label_)
    l = relabel[size_t(l)];
  // Surface points.
  auto frac = [&](int i, int j, int k) {
    return Contains(i, j, k) ? Fraction_[size_t(Index(i, j, k))] : 0.0f;
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const float f0 = frac(i, j, k);
        if (f0 < 0.5f)
          continue;
        const Vec3 g{frac(i + 1, j, k) - frac(i - 1, j, k), frac(i, j + 1, k) - frac(i, j - 1, k),
                     frac(i, j, k + 1) - frac(i, j, k - 1)};
        const Vec3 nrm = Normalized(Scale(g, -1));
        if (Norm(nrm) == 0)
          continue;
        const Vec3 c = Centre(i, j, k);
        for (int a = 0; a < 3; ++a)
          for (int d = -1; d <= 1; d += 2) {
            int q[3] = {i, j, k};
            q[a] += d;
            const float f1 = frac(q[0], q[1], q[2]);
            if (f1 >= 0.5f)
              continue;
            const double t = (f0 - 0.5) / std::max(1e-6, double(f0 - f1));
            Vec3 p = c;
            p[a] += d * t * Spacing_;
            Surface_.push_back({p, nrm, Label_[size_t(Index(i, j, k))]});
          }
      }
}

int SegmentedBone::LabelAt(const Vec3& p) const {
  const int i = int(std::lround((p[0] - Origin_[0]) / Spacing_));
  const int j = int(std::lround((p[1] - Origin_[1]) / Spacing_));
  const int k = int(std::lround((p[2] - Origin_[2]) / Spacing_));
  return Contains(i, j, k) ? Label_[size_t(Index(i, j, k))] : 0;
}

} // namespace bm
