#include "bmVoxmapResampler.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <vector>

namespace bm {

float MaterialScaleFromHU(float hu, const MaterialMapping& m) {
  if (std::isnan(hu))
    return 1.0f;
  return std::clamp(hu / m.corticalHU, m.minScale, 1.0f);
}

int CellsNoFinerThan(double longestMm, double spacingMm) {
  if (!(spacingMm > 0) || !std::isfinite(spacingMm) || !(longestMm > 0) ||
      !std::isfinite(longestMm))
    return 0;
  return std::max(8, int(std::min(std::floor(longestMm / spacingMm + 1e-9), 1e9)));
}

VoxmapGrid GridForBox(const Box3& box, int resolution) {
  if (resolution < 1)
    throw std::invalid_argument("voxmap resolution must be at least 1");
  double longest = 0;
  for (int a = 0; a < 3; ++a) {
    double e = box.hi[a] - box.lo[a];
    if (!(e > 0) || !std::isfinite(e))
      throw std::invalid_argument("voxmap box is empty along an axis");
    longest = std::max(longest, e);
  }
  VoxmapGrid g;
  g.spacing = longest / resolution;
  for (int a = 0; a < 3; ++a) {
    double cells = (box.hi[a] - box.lo[a]) / g.spacing;
    g.dims[a] = std::max(1, int(std::ceil(cells - 1e-9)));
    g.origin[a] = box.lo[a] + 0.5 * g.spacing;
  }
  return g;
}

uint64_t VoxmapBytes(const VoxmapGrid& g) {
  const auto pitch = Voxmap::PitchFor(g.dims); // the rows and slices as the voxmap pads them
  const uint64_t n = uint64_t(pitch[0]) * uint64_t(pitch[1]) * uint64_t(g.dims[2]);
  return n * (sizeof(Voxmap::Fill) + sizeof(float)) +
         n / (Voxmap::kBrick * Voxmap::kBrick * Voxmap::kBrick) * 4 + 4096;
}

namespace {

struct Sampler {
  const float* F = nullptr;
  const float* BH = nullptr;
  int nx = 0, ny = 0, nz = 0;
  double A[3][3]{}; // world offset (mm) -> continuous index
  double o[3]{};    // CT origin (mm)

  float At(int i, int j, int k) const {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz)
      return 0.0f;
    return F[i + int64_t(nx) * (j + int64_t(ny) * k)];
  }
  /// Bone fraction at continuous CT index c: trilinear interpolation of the voxel fractions
  /// (0 outside the CT).
  double Share(const double c[3]) const {
    int i0[3];
    double t[3];
    for (int a = 0; a < 3; ++a) {
      double f = std::floor(c[a]);
      i0[a] = int(f);
      t[a] = c[a] - f;
    }
    float v[8];
    bool all0 = true, all1 = true;
    for (int q = 0; q < 8; ++q) {
      v[q] = At(i0[0] + (q & 1), i0[1] + (q >> 1 & 1), i0[2] + (q >> 2 & 1));
      all0 &= v[q] == 0.0f;
      all1 &= v[q] == 1.0f;
    }
    if (all0)
      return 0.0;
    if (all1)
      return 1.0;
    const double x = t[0], y = t[1], z = t[2];
    const double c00 = v[0] + (v[1] - v[0]) * x, c10 = v[2] + (v[3] - v[2]) * x;
    const double c01 = v[4] + (v[5] - v[4]) * x, c11 = v[6] + (v[7] - v[6]) * x;
    const double c0 = c00 + (c10 - c00) * y, c1 = c01 + (c11 - c01) * y;
    return c0 + (c1 - c0) * z;
  }
  /// Bone HU near continuous index c (nearest voxel, else the nearest defined within one voxel).
  float BoneHU(const double c[3]) const {
    int n[3];
    for (int a = 0; a < 3; ++a)
      n[a] = int(std::floor(c[a] + 0.5));
    float best = std::numeric_limits<float>::quiet_NaN();
    for (int r = 0; r <= 1; ++r)
      for (int dk = -r; dk <= r; ++dk)
        for (int dj = -r; dj <= r; ++dj)
          for (int di = -r; di <= r; ++di) {
            int i = n[0] + di, j = n[1] + dj, k = n[2] + dk;
            if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz)
              continue;
            float h = BH[i + int64_t(nx) * (j + int64_t(ny) * k)];
            if (!std::isnan(h) && (std::isnan(best) || h > best))
              best = h;
          }
    return best;
  }
};

void SharpenConservingVolume(Voxmap& vm) {
  // The interpolated fractions ramp over about one CT voxel on each side of the surface; a stretch
  // g(f) = clamp(0.5 + kSharpen (f - c), 0, 1) of the bone voxels' fills (void stays void) takes
  // the faint outer part of the ramp to void and the inner part to full, with c chosen by
  // bisection so that the total bone volume is unchanged.
  constexpr double kSharpen = 3.0;
  Voxmap::Fill* fill = vm.MutableFill();
  const auto& d = vm.Dims();
  std::vector<int64_t> bone;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        if (fill[vm.Index(i, j, k)] > 0)
          bone.push_back(vm.Index(i, j, k));
  if (bone.empty())
    return;
  double total = 0;
  for (int64_t v : bone)
    total += double(fill[v]) / Voxmap::kFull;
  auto g = [](double f, double c) { return std::clamp(0.5 + kSharpen * (f - c), 0.0, 1.0); };
  auto volume = [&](double c) {
    double sum = 0;
    for (int64_t v : bone)
      sum += g(double(fill[v]) / Voxmap::kFull, c);
    return sum;
  };
  double lo = -0.5, hi = 1.5; // volume(c) falls as c rises
  for (int it = 0; it < 40; ++it) {
    const double c = 0.5 * (lo + hi);
    (volume(c) > total ? lo : hi) = c;
  }
  const double c = 0.5 * (lo + hi);
  for (int64_t v : bone)
    fill[v] = Voxmap::Fill(std::llround(g(double(fill[v]) / Voxmap::kFull, c) * Voxmap::kFull));
}

} // namespace

Voxmap ResampleToVoxmap(const BoneSegmentation& seg, const VoxmapGrid& grid,
                        const MaterialMapping& material, const Progress& progress, int threads) {
  const FractionImage* fr = seg.fraction.GetPointer();
  const auto region = fr->GetLargestPossibleRegion();
  Sampler s;
  s.F = fr->GetBufferPointer();
  s.BH = seg.boneHU->GetBufferPointer();
  s.nx = int(region.GetSize(0));
  s.ny = int(region.GetSize(1));
  s.nz = int(region.GetSize(2));
  const auto sp = fr->GetSpacing();
  const auto D = fr->GetDirection();
  const auto O = fr->GetOrigin();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      s.A[r][c] = D[c][r] / sp[r]; // diag(1/s) * D^T
    s.o[r] = O[r];
  }
  // Samples per axis: at least 1.5 per CT voxel across the voxmap voxel, so that the midpoint
  // rule integrates the piecewise-trilinear field closely.
  const double minSp = std::min({sp[0], sp[1], sp[2]});
  const int m = std::clamp(int(std::ceil(1.5 * grid.spacing / minSp - 1e-9)), 1, 8);

  Voxmap vm(grid.dims, grid.spacing, grid.origin);
  vm.SetMaterial(0, 1.0f); // allocate the material array before the workers write it
  Voxmap::Fill* fill = vm.MutableFill();
  const int nz = grid.dims[2], ny = grid.dims[1], nx = grid.dims[0];
  std::atomic<int> nextSlice{0}, doneSlices{0};
  std::atomic<bool> stop{false};
  const double inv = 1.0 / (double(m) * m * m);

  auto doSlice = [&](int k) {
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        double sum = 0;
        for (int qk = 0; qk < m; ++qk)
          for (int qj = 0; qj < m; ++qj)
            for (int qi = 0; qi < m; ++qi) {
              double p[3] = {grid.origin[0] + grid.spacing * (i + ((qi + 0.5) / m - 0.5)),
                             grid.origin[1] + grid.spacing * (j + ((qj + 0.5) / m - 0.5)),
                             grid.origin[2] + grid.spacing * (k + ((qk + 0.5) / m - 0.5))};
              double c[3];
              for (int r = 0; r < 3; ++r)
                c[r] = s.A[r][0] * (p[0] - s.o[0]) + s.A[r][1] * (p[1] - s.o[1]) +
                       s.A[r][2] * (p[2] - s.o[2]);
              sum += s.Share(c);
            }
        const int64_t v = vm.Index(i, j, k);
        const auto f = Voxmap::Fill(std::llround(sum * inv * Voxmap::kFull));
        fill[v] = f;
        if (f > 0) {
          double p[3] = {grid.origin[0] + grid.spacing * i, grid.origin[1] + grid.spacing * j,
                         grid.origin[2] + grid.spacing * k};
          double c[3];
          for (int r = 0; r < 3; ++r)
            c[r] = s.A[r][0] * (p[0] - s.o[0]) + s.A[r][1] * (p[1] - s.o[1]) +
                   s.A[r][2] * (p[2] - s.o[2]);
          vm.SetMaterial(v, MaterialScaleFromHU(s.BoneHU(c), material));
        } else {
          vm.SetMaterial(v, 1.0f);
        }
      }
  };
  auto worker = [&]() {
    for (int k; !stop.load(std::memory_order_relaxed) && (k = nextSlice.fetch_add(1)) < nz;) {
      doSlice(k);
      doneSlices.fetch_add(1);
    }
  };
  int nt = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
  nt = std::clamp(nt, 1, std::max(1, nz));
  std::vector<std::thread> pool;
  for (int t = 1; t < nt; ++t)
    pool.emplace_back(worker);
  // The calling thread works too, and alone reports progress (the callback need not be
  // thread-safe).
  try {
    for (int k; (k = nextSlice.fetch_add(1)) < nz;) {
      progress(double(doneSlices.load()) / nz, "resampling into the voxmap");
      doSlice(k);
      doneSlices.fetch_add(1);
    }
  } catch (...) {
    stop = true;
    for (auto& t : pool)
      t.join();
    throw;
  }
  for (auto& t : pool)
    t.join();
  SharpenConservingVolume(vm);
  vm.RebuildOccupancy();
  progress(1.0, "resampling into the voxmap");
  return vm;
}

} // namespace bm
