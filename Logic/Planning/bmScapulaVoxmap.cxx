#include "bmScapulaVoxmap.h"

#include <cmath>
#include <stdexcept>

namespace bm {

Voxmap MakeScapulaVoxmap(const ScapulaPhantom& ph, double sp, int samples, double marginMm) {
  if (!(sp > 0) || samples < 1 || !(marginMm >= 0))
    throw std::invalid_argument("scapula voxmap: spacing must be > 0 mm, samples >= 1, margin "
                                ">= 0 mm");
  Vec3 lo, hi;
  ph.Bounds(lo, hi);
  std::array<int, 3> dims;
  Vec3 origin;
  for (int a = 0; a < 3; ++a) {
    lo[a] -= marginMm, hi[a] += marginMm;
    dims[a] = int(std::ceil((hi[a] - lo[a]) / sp));
    origin[a] = lo[a] + 0.5 * sp;
  }
  Voxmap vm(dims, sp, origin);
  const float cancellous = ph.Params().cancellousHU / ph.Params().corticalHU;
  const double h = 0.5 * sp;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const Vec3 c{origin[0] + i * sp, origin[1] + j * sp, origin[2] + k * sp};
        const auto t0 = ph.TissueAt(c);
        bool uniform = true;
        for (int q = 0; q < 8 && uniform; ++q)
          uniform = ph.TissueAt({c[0] + ((q & 1) ? h : -h), c[1] + ((q & 2) ? h : -h),
                                 c[2] + ((q & 4) ? h : -h)}) == t0;
        double frac;
        if (uniform) {
          frac = t0 == ScapulaPhantom::Tissue::Soft ? 0.0 : 1.0;
        } else {
          int bone = 0;
          for (int z = 0; z < samples; ++z)
            for (int y = 0; y < samples; ++y)
              for (int x = 0; x < samples; ++x)
                bone += ph.TissueAt({c[0] + ((x + 0.5) / samples - 0.5) * sp,
                                     c[1] + ((y + 0.5) / samples - 0.5) * sp,
                                     c[2] + ((z + 0.5) / samples - 0.5) * sp}) !=
                        ScapulaPhantom::Tissue::Soft;
          frac = double(bone) / (samples * samples * samples);
        }
        if (frac <= 0)
          continue;
        const int64_t idx = vm.Index(i, j, k);
        vm.SetFill(idx, Voxmap::Fill(std::lround(frac * Voxmap::kFull)));
        vm.SetMaterial(idx, t0 == ScapulaPhantom::Tissue::Cancellous ? cancellous : 1.0f);
      }
  return vm;
}

void BridgeJointSpace(Voxmap& v, const ScapulaPhantom& ph, double radiusMm) {
  const ScapulaTruth& t = ph.Truth();
  for (int k = 0; k < v.Dims()[2]; ++k)
    for (int j = 0; j < v.Dims()[1]; ++j)
      for (int i = 0; i < v.Dims()[0]; ++i) {
        const Vec3 p{v.Origin()[0] + i * v.Spacing(), v.Origin()[1] + j * v.Spacing(),
                     v.Origin()[2] + k * v.Spacing()};
        const Vec3 d = Sub(p, t.glenoidCentre);
        const double w = Dot(d, t.faceNormal);
        if (w > -1 && w < 6 && Norm(AddScaled(d, t.faceNormal, -w)) < radiusMm &&
            Distance(p, t.humeralHeadCentre) > t.humeralHeadRadiusMm - 1)
          v.SetFill(v.Index(i, j, k), Voxmap::kFull);
      }
}

} // namespace bm
