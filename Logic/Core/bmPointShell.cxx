#include "bmPointShell.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include "bmMorton.h"

namespace bm {

namespace {
constexpr double kPi = std::numbers::pi;

// Nearest point on the tool's half-section outline, through a uniform bucket grid in (rho, z).
class ProfileLocator {
public:
  struct Hit {
    double s = 0;            // arc length along the outline, mm
    double rho = 0;          // radius of the nearest outline point, mm
    double nRho = 0, nZ = 0; // outward unit normal in (rho, z)
    EdgeKind kind = EdgeKind::None;
  };

  ProfileLocator(std::vector<ProfilePoint> pts, double cell) : P_(std::move(pts)), Cell_(cell) {
    S_.resize(P_.size(), 0.0);
    for (size_t i = 1; i < P_.size(); ++i)
      S_[i] = S_[i - 1] + std::hypot(P_[i].rho - P_[i - 1].rho, P_[i].z - P_[i - 1].z);
    double zLo = 1e300, zHi = -1e300, rHi = 0;
    for (const auto& p : P_) {
      zLo = std::min(zLo, p.z);
      zHi = std::max(zHi, p.z);
      rHi = std::max(rHi, p.rho);
    }
    R0_ = -Cell_;
    Z0_ = zLo - Cell_;
    NR_ = int((rHi + 2 * Cell_) / Cell_) + 1;
    NZ_ = int((zHi - zLo + 2 * Cell_) / Cell_) + 1;
    Buckets_.assign(size_t(NR_) * NZ_, {});
    for (size_t i = 0; i + 1 < P_.size(); ++i) {
      const auto &a = P_[i], &b = P_[i + 1];
      int r0 = CellR(std::min(a.rho, b.rho)), r1 = CellR(std::max(a.rho, b.rho));
      int z0 = CellZ(std::min(a.z, b.z)), z1 = CellZ(std::max(a.z, b.z));
      for (int zz = z0; zz <= z1; ++zz)
        for (int rr = r0; rr <= r1; ++rr)
          Buckets_[size_t(zz) * NR_ + rr].push_back(uint32_t(i));
    }
  }

  double TotalLength() const { return S_.back(); }
  const std::vector<ProfilePoint>& Points() const { return P_; }
  const std::vector<double>& ArcLengths() const { return S_; }

  // Nearest outline point to (rho, z); the query must lie within ~2 cells of the outline.
  Hit Nearest(double rho, double z) const {
    Hit best;
    double bestD = 1e300;
    const int cr = CellR(rho), cz = CellZ(z);
    for (int zz = std::max(cz - 1, 0); zz <= std::min(cz + 1, NZ_ - 1); ++zz)
      for (int rr = std::max(cr - 1, 0); rr <= std::min(cr + 1, NR_ - 1); ++rr)
        for (uint32_t i : Buckets_[size_t(zz) * NR_ + rr]) {
          const auto &a = P_[i], &b = P_[i + 1];
          const double dr = b.rho - a.rho, dz = b.z - a.z, len2 = dr * dr + dz * dz;
          if (len2 <= 0)
            continue;
          const double t = std::clamp(((rho - a.rho) * dr + (z - a.z) * dz) / len2, 0.0, 1.0);
          const double pr = a.rho + t * dr, pz = a.z + t * dz;
          const double d = (rho - pr) * (rho - pr) + (z - pz) * (z - pz);
          if (d < bestD) {
            bestD = d;
            const double len = std::sqrt(len2);
            best.s = S_[i] + t * len;
            best.rho = pr;
            best.nRho = dz / len; // the outline runs counter-clockwise: outward = (dz, -drho)
            best.nZ = -dr / len;
            best.kind = a.kind;
          }
        }
    if (bestD == 1e300)
      throw std::logic_error("point shell: surface element far from the tool outline");
    return best;
  }

  // Area (mm^2) of the surface of revolution swept by the outline between arc lengths s0 and s1.
  double Area(double s0, double s1) const {
    double area = 0;
    for (size_t i = 0; i + 1 < P_.size(); ++i) {
      const double a = std::max(s0, S_[i]), b = std::min(s1, S_[i + 1]);
      if (b <= a)
        continue;
      const double len = S_[i + 1] - S_[i];
      auto rhoAt = [&](double s) {
        return P_[i].rho + (P_[i + 1].rho - P_[i].rho) * (s - S_[i]) / len;
      };
      area += kPi * (rhoAt(a) + rhoAt(b)) * (b - a);
    }
    return area;
  }

private:
  int CellR(double rho) const { return std::clamp(int((rho - R0_) / Cell_), 0, NR_ - 1); }
  int CellZ(double z) const { return std::clamp(int((z - Z0_) / Cell_), 0, NZ_ - 1); }
  std::vector<ProfilePoint> P_;
  std::vector<double> S_;
  double Cell_, R0_ = 0, Z0_ = 0;
  int NR_ = 0, NZ_ = 0;
  std::vector<std::vector<uint32_t>> Buckets_;
};

struct RawElement {
  uint64_t code;
  std::array<float, 3> areaNormal;
  std::array<float, 3> unitNormal;
  uint16_t bin;
  float delta;
};

double WrapAngle(double a) {
  a = std::fmod(a + kPi, 2 * kPi);
  if (a < 0)
    a += 2 * kPi;
  return a - kPi;
}
} // namespace

PointShell PointShell::Build(const ToolModel& tool, int resolution, LipMode mode, int blockSize) {
  if (resolution < 8 || resolution > int(kMortonMaxCoord))
    throw std::invalid_argument("point shell resolution must be in [8, 2^21), got " +
                                std::to_string(resolution));
  if (blockSize < 1)
    throw std::invalid_argument("point shell block size must be >= 1");
  PointShell ps;
  ps.Resolution_ = resolution;
  ps.Mode_ = mode;
  const double Ro = tool.OuterRadius();
  const auto zr = tool.AxialRange();
  const std::array<double, 3> extent{2 * Ro, 2 * Ro, zr[1] - zr[0]};
  const double h = std::max({extent[0], extent[1], extent[2]}) / resolution;
  ps.Spacing_ = h;
  std::array<int, 3> dims{};
  const std::array<double, 3> lo{-Ro, -Ro, zr[0]};
  for (int a = 0; a < 3; ++a) {
    dims[a] = std::max(1, int(std::ceil(extent[a] / h - 1e-9)));
    // Centre the grid on the bounding box, so the shell is symmetric about the axis.
    ps.Origin_[a] = lo[a] + 0.5 * (extent[a] - dims[a] * h) + 0.5 * h;
  }

  // Inside interval [kLo, kHi] of each column (empty when kLo > kHi).
  const size_t nCol = size_t(dims[0]) * dims[1];
  std::vector<int> kLo(nCol, 1), kHi(nCol, 0);
  for (int j = 0; j < dims[1]; ++j)
    for (int i = 0; i < dims[0]; ++i) {
      const double x = ps.Origin_[0] + i * h, y = ps.Origin_[1] + j * h;
      double zl = 0, zh = 0;
      if (!tool.ZRange(std::hypot(x, y), zl, zh))
        continue;
      const int a = int(std::ceil((zl - ps.Origin_[2]) / h - 1e-9));
      const int b = int(std::floor((zh - ps.Origin_[2]) / h + 1e-9));
      kLo[size_t(j) * dims[0] + i] = std::max(a, 0);
      kHi[size_t(j) * dims[0] + i] = std::min(b, dims[2] - 1);
    }

  ProfileLocator loc(tool.Profile(0.25 * h), 2.0 * h);

  // Radial force bins per edge kind, about one spacing wide.
  struct KindBins {
    EdgeKind kind;
    double r0 = 0, dr = 0;
    int first = 0, count = 0;
  };
  std::vector<KindBins> kb;
  for (EdgeKind k : {EdgeKind::Chisel, EdgeKind::Lip}) {
    auto range = tool.EdgeRange(k);
    if (!(range[1] > range[0]))
      continue;
    KindBins b{k, range[0], 0, int(ps.ForceBins_.size()), 0};
    b.count = std::max(1, int(std::ceil((range[1] - range[0]) / h)));
    b.dr = (range[1] - range[0]) / b.count;
    for (int i = 0; i < b.count; ++i)
      ps.ForceBins_.push_back({range[0] + (i + 0.5) * b.dr, b.dr, k});
    kb.push_back(b);
  }
  if (ps.ForceBins_.size() >= kNoBin)
    throw std::invalid_argument("point shell resolution too fine for 16-bit force bins");
  const int nLips = tool.NumLips();

  // Surface elements: inside voxels with a face neighbour outside.
  std::vector<RawElement> raw;
  std::vector<double> sOf; // arc length per element (for the area share)
  std::vector<int> lipOf;  // lip index per cutting element (instantaneous), else 0
  auto inside = [&](int i, int j, int k) {
    if (i < 0 || j < 0 || i >= dims[0] || j >= dims[1])
      return false;
    const size_t c = size_t(j) * dims[0] + i;
    return k >= kLo[c] && k <= kHi[c];
  };
  for (int j = 0; j < dims[1]; ++j)
    for (int i = 0; i < dims[0]; ++i) {
      const size_t c = size_t(j) * dims[0] + i;
      for (int k = kLo[c]; k <= kHi[c]; ++k) {
        if (k != kLo[c] && k != kHi[c] && inside(i - 1, j, k) && inside(i + 1, j, k) &&
            inside(i, j - 1, k) && inside(i, j + 1, k)) {
          // Interior run: jump to where a neighbour column ends.
          int stop = kHi[c] - 1;
          for (auto [di, dj] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}})
            stop = std::min(stop, kHi[size_t(j + dj) * dims[0] + (i + di)]);
          k = std::max(k, stop); // the loop's ++k visits stop + 1 next
          continue;
        }
        const double x = ps.Origin_[0] + i * h, y = ps.Origin_[1] + j * h,
                     z = ps.Origin_[2] + k * h;
        const double rho = std::hypot(x, y);
        const auto hit = loc.Nearest(rho, z);
        const double cphi = rho > 0 ? x / rho : 1.0, sphi = rho > 0 ? y / rho : 0.0;
        RawElement e{};
        e.unitNormal = {float(hit.nRho * cphi), float(hit.nRho * sphi), float(hit.nZ)};
        e.bin = kNoBin;
        bool cutting = false;
        int lip = 0;
        if (hit.kind != EdgeKind::None) {
          for (const auto& b : kb)
            if (b.kind == hit.kind) {
              int bi = std::clamp(int((hit.rho - b.r0) / b.dr), 0, b.count - 1);
              cutting = true;
              if (mode == LipMode::Instantaneous) {
                // Cuts only within one spacing of a lip at spindle angle 0.
                cutting = false;
                const double phi = std::atan2(y, x);
                for (int l = 0; l < nLips && !cutting; ++l)
                  if (std::abs(WrapAngle(phi - tool.LipAzimuth(l, hit.rho))) *
                          std::max(rho, 0.5 * h) <=
                      h) {
                    cutting = true;
                    lip = l;
                  }
              }
              if (cutting)
                e.bin = uint16_t(b.first + bi);
            }
        }
        e.code = PackElement(uint32_t(i), uint32_t(j), uint32_t(k), cutting);
        raw.push_back(e);
        sOf.push_back(hit.s);
        lipOf.push_back(lip);
      }
    }

  // Area shares: elements binned by arc length, each bin's swept area split evenly.
  const int nS = std::max(1, int(std::ceil(loc.TotalLength() / h)));
  const double ds = loc.TotalLength() / nS;
  std::vector<int> sCount(nS, 0);
  for (double s : sOf)
    sCount[std::clamp(int(s / ds), 0, nS - 1)]++;
  std::vector<double> sArea(nS);
  for (int b = 0; b < nS; ++b)
    sArea[b] = loc.Area(b * ds, (b + 1) * ds);
  // Edge shares: time-averaged N_c dr / count per radial bin; instantaneous dr / count per lip and
  // bin.
  const size_t nB = ps.ForceBins_.size();
  std::vector<int> binCount(nB * (mode == LipMode::Instantaneous ? nLips : 1), 0);
  auto binSlot = [&](size_t e) {
    return size_t(raw[e].bin) + (mode == LipMode::Instantaneous ? nB * lipOf[e] : 0);
  };
  for (size_t e = 0; e < raw.size(); ++e)
    if (raw[e].bin != kNoBin)
      binCount[binSlot(e)]++;
  // Radial extent each slot stands for. A bin that no element of a lip landed in (a single lip
  // of the instantaneous shell is one spacing wide, so some bins stay empty) hands its extent to
  // the nearest filled bin of the same lip and kind, so no part of an edge is lost.
  std::vector<double> slotDr(binCount.size(), 0.0);
  for (size_t slot = 0; slot < binCount.size(); ++slot) {
    const size_t bin = slot % nB, lipBase = slot - bin;
    const KindBins* k = nullptr;
    for (const auto& b : kb)
      if (int(bin) >= b.first && int(bin) < b.first + b.count)
        k = &b;
    if (binCount[slot] > 0) {
      slotDr[slot] += k->dr;
      continue;
    }
    // Nearest filled bin of the same kind and lip (ties go inward).
    for (int dist = 1; dist < k->count; ++dist) {
      const int lo = int(bin) - dist, hi = int(bin) + dist;
      if (lo >= k->first && binCount[lipBase + size_t(lo)] > 0) {
        slotDr[lipBase + size_t(lo)] += k->dr;
        break;
      }
      if (hi < k->first + k->count && binCount[lipBase + size_t(hi)] > 0) {
        slotDr[lipBase + size_t(hi)] += k->dr;
        break;
      }
    }
  }
  for (size_t e = 0; e < raw.size(); ++e) {
    const int sb = std::clamp(int(sOf[e] / ds), 0, nS - 1);
    const double area = sArea[sb] / sCount[sb];
    for (int a = 0; a < 3; ++a)
      raw[e].areaNormal[a] = float(area * raw[e].unitNormal[a]);
    if (raw[e].bin != kNoBin) {
      const double lips = mode == LipMode::Instantaneous ? 1.0 : double(nLips);
      raw[e].delta = float(lips * slotDr[binSlot(e)] / binCount[binSlot(e)]);
      ps.NumCutting_++;
    }
  }

  // Axial shares made exact per column: the tool is fed along its axis, and a column's elements
  // facing down (or up) must sweep exactly the column's cross-section (h^2 times the part of the
  // cell inside the tool's footprint). The arc-length shares above only hold on average (a column
  // on a slope holds one or two elements), and a voxel under too much element area empties
  // before the tool surface has passed it. Elements on walls (|n_z| <= 0.05) keep their shares.
  {
    std::vector<double> sum(2 * nCol, 0.0);
    auto colOf = [&](const RawElement& e) {
      const auto ijk = ElementCoords(e.code);
      return size_t(ijk[1]) * dims[0] + ijk[0];
    };
    for (const auto& e : raw)
      if (std::abs(e.unitNormal[2]) > 0.05f)
        sum[2 * colOf(e) + (e.unitNormal[2] > 0)] += std::abs(e.areaNormal[2]);
    constexpr int kSub = 4;
    std::vector<double> scale(2 * nCol, 1.0);
    for (size_t c = 0; c < nCol; ++c) {
      if (sum[2 * c] == 0 && sum[2 * c + 1] == 0)
        continue;
      const int i = int(c % size_t(dims[0])), j = int(c / size_t(dims[0]));
      int in = 0;
      double zl = 0, zh = 0;
      for (int a = 0; a < kSub; ++a)
        for (int b = 0; b < kSub; ++b) {
          const double x = ps.Origin_[0] + (i - 0.5 + (a + 0.5) / kSub) * h;
          const double y = ps.Origin_[1] + (j - 0.5 + (b + 0.5) / kSub) * h;
          in += tool.ZRange(std::hypot(x, y), zl, zh);
        }
      const double target = h * h * in / (kSub * kSub);
      for (int g = 0; g < 2; ++g)
        if (sum[2 * c + g] > 0)
          scale[2 * c + g] = target / sum[2 * c + g];
    }
    for (auto& e : raw)
      if (std::abs(e.unitNormal[2]) > 0.05f)
        e.areaNormal[2] = float(e.areaNormal[2] * scale[2 * colOf(e) + (e.unitNormal[2] > 0)]);
  }

  std::sort(raw.begin(), raw.end(),
            [](const RawElement& a, const RawElement& b) { return a.code < b.code; });
  const size_t n = raw.size();
  ps.Codes_.resize(n);
  ps.AreaNormal_.resize(n);
  ps.Bin_.resize(n);
  ps.Delta_.resize(n);
  for (size_t e = 0; e < n; ++e) {
    ps.Codes_[e] = raw[e].code;
    ps.AreaNormal_[e] = raw[e].areaNormal;
    ps.Bin_[e] = raw[e].bin;
    ps.Delta_[e] = raw[e].bin == kNoBin ? 0.0f : raw[e].delta;
  }
  ps.RadialDir_.resize(n);
  for (size_t e = 0; e < n; ++e) {
    const auto ijk = ElementCoords(ps.Codes_[e]);
    const double px = ps.Origin_[0] + h * ijk[0], py = ps.Origin_[1] + h * ijk[1];
    const double rho = std::sqrt(px * px + py * py);
    ps.RadialDir_[e] = {rho > 0 ? px / rho : 1.0, rho > 0 ? py / rho : 0.0};
  }
  for (size_t b = 0; b < n; b += size_t(blockSize)) {
    ShellBlock blk;
    blk.begin = uint32_t(b);
    blk.end = uint32_t(std::min(n, b + size_t(blockSize)));
    blk.lo = {1e30f, 1e30f, 1e30f};
    blk.hi = {-1e30f, -1e30f, -1e30f};
    blk.nLo = {1, 1, 1};
    blk.nHi = {-1, -1, -1};
    for (uint32_t e = blk.begin; e < blk.end; ++e) {
      const auto p = ps.Position(e);
      for (int a = 0; a < 3; ++a) {
        blk.lo[a] = std::min(blk.lo[a], float(p[a] - 0.5 * h));
        blk.hi[a] = std::max(blk.hi[a], float(p[a] + 0.5 * h));
        blk.nLo[a] = std::min(blk.nLo[a], raw[e].unitNormal[a]);
        blk.nHi[a] = std::max(blk.nHi[a], raw[e].unitNormal[a]);
      }
      blk.hasCutting |= ElementIsCutting(raw[e].code);
    }
    ps.Blocks_.push_back(blk);
  }
  return ps;
}

std::array<double, 3> PointShell::Position(size_t e) const {
  const auto ijk = ElementCoords(Codes_[e]);
  return {Origin_[0] + ijk[0] * Spacing_, Origin_[1] + ijk[1] * Spacing_,
          Origin_[2] + ijk[2] * Spacing_};
}

double PointShell::SurfaceArea() const {
  double a = 0;
  for (const auto& n : AreaNormal_)
    a += std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
  return a;
}

size_t PointShell::MemoryBytes() const {
  return Codes_.size() * (sizeof(uint64_t) + sizeof(std::array<float, 3>) + sizeof(uint16_t) +
                          sizeof(float) + sizeof(std::array<double, 2>)) +
         ForceBins_.size() * sizeof(ForceBin) + Blocks_.size() * sizeof(ShellBlock);
}

} // namespace bm
