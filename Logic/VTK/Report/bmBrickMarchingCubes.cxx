// bmBrickMarchingCubes.cxx - see bmBrickMarchingCubes.h.
#include "bmBrickMarchingCubes.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <type_traits>

#include <vtkMarchingCubesTriangleCases.h>
#include <vtkMath.h>

namespace bm {

namespace {
// VTK's marching-cubes numbering (vtkMarchingCubes, vtkMarchingCubesTriangleCases): corner q of a
// cell sits at (q & 1) ^ ((q >> 1) & 1), (q >> 1) & 1, q >> 2, i.e. (0,0,0), (1,0,0), (1,1,0),
// (0,1,0), then the same at z = 1; edge e joins the corners {0,1}, {1,2}, {3,2}, {0,3}, {4,5},
// {5,6}, {7,6}, {4,7}, {0,4}, {1,5}, {3,7}, {2,6}. Below: each edge as its lower-index corner and
// its axis (the vertex is interpolated from the lower sample, as vtkFlyingEdges3D does).
constexpr int kEdgeCorner[12][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0},
                                    {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {0, 0, 1},
                                    {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
constexpr int kEdgeAxis[12] = {0, 1, 0, 1, 0, 1, 0, 1, 2, 2, 2, 2};
} // namespace

BrickMarchingCubes::BrickMarchingCubes(int cells, double iso)
    : B_(cells), N_(cells + 3), Iso_(iso) {
  if (cells < 2 || cells > 62)
    throw std::invalid_argument("BrickMarchingCubes: cells must be in 2..62");
  if (!(iso > 0.0 && iso < 1.0))
    throw std::invalid_argument("BrickMarchingCubes: iso must be in (0, 1)");
  const size_t n = size_t(N_) * N_ * N_, m = size_t(cells + 1);
  S_.assign(n, 0.0f);
  F_.assign(n, 0);
  Above_.assign(n + 8, 0);
  RowBits_.assign(size_t(N_) * N_, 0);
  // The smallest fill whose fraction (fill / kFull, exact in double) is >= iso.
  IsoFill_ = Voxmap::Fill(std::ceil(iso * double(Voxmap::kFull)));
  Mask_.assign(m * m, 0);
  EdgeVertex_.assign(3 * n, 0);
  // At most one vertex per edge of the brick's samples, at most 5 triangles per cell.
  Points_.assign(3 * 3 * m * m * m, 0.0f);
  Normals_.assign(3 * 3 * m * m * m, 0.0f);
  Triangles_.assign(3 * 5 * size_t(cells) * cells * cells, 0);
}

bool BrickMarchingCubes::AnyBone(const Voxmap& bone, const std::array<int, 3>& lo,
                                 const std::array<int, 3>& hi) {
  const auto& d = bone.Dims();
  std::array<int, 3> vlo, vhi;
  for (int a = 0; a < 3; ++a) {
    if (hi[a] < 0 || lo[a] >= d[a])
      return false; // only pad samples: void
    vlo[a] = std::max(lo[a], 0) / Voxmap::kBrick;
    vhi[a] = std::min(hi[a], d[a] - 1) / Voxmap::kBrick;
  }
  for (int k = vlo[2]; k <= vhi[2]; ++k)
    for (int j = vlo[1]; j <= vhi[1]; ++j)
      for (int i = vlo[0]; i <= vhi[0]; ++i)
        if (bone.BrickCount(bone.BrickIndex(i, j, k)) > 0)
          return true;
  return false;
}

void BrickMarchingCubes::Prefetch(const Voxmap& bone, const std::array<int, 3>& first) const {
  const std::array<int, 3> g0{first[0] - 1, first[1] - 1, first[2] - 1};
  const auto& d = bone.Dims();
  if (g0[0] + N_ - 1 < 0 || g0[0] >= d[0] ||
      !AnyBone(bone, g0, {g0[0] + N_ - 1, g0[1] + N_ - 1, g0[2] + N_ - 1}))
    return; // Extract reads nothing (or only the pad)
  PrefetchSlices(bone, g0, 0, kSlicesAhead);
}

void BrickMarchingCubes::PrefetchSlices(const Voxmap& bone, const std::array<int, 3>& g0, int z0,
                                        int z1) const {
  // Each row is one or two cache lines the hardware prefetcher does not guess (rows lie px fills
  // apart, slices px py: Voxmap::Pitch).
  const auto& d = bone.Dims();
  const int n = N_;
  const int xLo = std::clamp(g0[0], 0, d[0] - 1), xHi = std::clamp(g0[0] + n - 1, 0, d[0] - 1);
  const Voxmap::Fill* fill = bone.FillData();
  for (int gz = std::max(g0[2] + z0, 0); gz < std::min(g0[2] + std::min(z1, n), d[2]); ++gz)
    for (int gy = std::max(g0[1], 0); gy < std::min(g0[1] + n, d[1]); ++gy) {
      const Voxmap::Fill* row = fill + bone.Index(0, gy, gz);
      __builtin_prefetch(row + xLo, 0, 3);
      __builtin_prefetch(row + xHi, 0, 3);
    }
}

void BrickMarchingCubes::Load(const Voxmap& bone, const std::array<int, 3>& first) {
  const auto& d = bone.Dims();
  const int n = N_;
  const std::array<int, 3> g0{first[0] - 1, first[1] - 1, first[2] - 1}; // box sample 0, voxels
  Voxmap::Fill* f = F_.data();
  uint64_t* bits = RowBits_.data();
  const Voxmap::Fill isoFill = IsoFill_;
  // The box's fills in the grid; void elsewhere. Each row's samples >= iso as bits (bit = box x):
  // a fill f is the fraction f / kFull exactly, which is >= iso exactly when f >= IsoFill_.
  const int xLo = std::clamp(-g0[0], 0, n), xHi = std::clamp(d[0] - g0[0], 0, n);
  for (int z = 0; z < n; ++z) {
    const int gz = g0[2] + z;
    if (xLo < xHi) // the slice kSlicesAhead on (Prefetch() asked for the first ones)
      PrefetchSlices(bone, g0, z + kSlicesAhead, z + kSlicesAhead + 1);
    for (int y = 0; y < n; ++y) {
      const int gy = g0[1] + y;
      Voxmap::Fill* row = f + int64_t(n) * (y + int64_t(n) * z);
      if (gz < 0 || gz >= d[2] || gy < 0 || gy >= d[1] || xLo >= xHi) {
        std::fill(row, row + n, Voxmap::Fill(0));
        bits[y + n * z] = 0;
        continue;
      }
      // The row's fills with relaxed atomic loads (a loop of its own: never merged or
      // vectorised), void outside the grid.
      std::fill(row, row + xLo, Voxmap::Fill(0));
      std::fill(row + xHi, row + n, Voxmap::Fill(0));
      bone.LoadFillRow(bone.Index(0, gy, gz) + g0[0] + xLo, xHi - xLo, row + xLo);
    }
  }
  // Classified in one pass over the whole box (vectorised: one byte per sample, 1 where >= iso),
  // then each row's bytes packed into bits eight at a time: for eight bytes b_i in {0, 1} (byte i
  // at bit 8 i of a little-endian word w), w * 0x0102040810204080 has b_i at bit 56 + i, the
  // other products landing on distinct bits below 56 or past 63, so nothing carries into them.
  static_assert(std::endian::native == std::endian::little, "the packing reads bytes as words");
  const int total = n * n * n;
  uint8_t* above = Above_.data();
  for (int i = 0; i < total; ++i)
    above[i] = uint8_t(f[i] >= isoFill);
  for (int r = 0; r < n * n; ++r) {
    const uint8_t* b = above + int64_t(r) * n;
    uint64_t rowBits = 0;
    for (int x = 0; x < n; x += 8) {
      uint64_t w;
      std::memcpy(&w, b + x, 8); // Above_ has 8 bytes to spare past the box
      if (n - x < 8)
        w &= ~uint64_t(0) >> (8 * (8 - (n - x)));
      rowBits |= ((w * 0x0102040810204080ull) >> 56) << x;
    }
    bits[r] = rowBits;
  }
}

void BrickMarchingCubes::Convert(const Voxmap& bone, const std::array<int, 3>& first) {
  const auto& d = bone.Dims();
  const int n = N_;
  const std::array<int, 3> g0{first[0] - 1, first[1] - 1, first[2] - 1};
  float* s = S_.data();
  const Voxmap::Fill* f = F_.data();
  constexpr float kScale = 1.0f / float(Voxmap::kFull); // a power of two: exact
  // One pass over the whole box, a fill <= 0 void: max(f, 0) as f & ~(f >> 31) (an arithmetic
  // shift: all ones for a negative fill), which GCC vectorises where it left std::max a branch.
  static_assert(std::is_same_v<Voxmap::Fill, int32_t>, "the mask is a 32-bit fill's sign");
  const int total = n * n * n;
  for (int i = 0; i < total; ++i)
    s[i] = float(f[i] & ~(f[i] >> 31)) * kScale;
  // Ghost samples one beyond the pad (-2 and Dims + 1 on one axis, the others within the padded
  // grid): -s of the sample two back, so that the central difference on the pad sample (value 0)
  // is the one-sided difference vtkFlyingEdges3D takes on its volume's boundary.
  const std::array<int64_t, 3> st{1, n, int64_t(n) * n};
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const int p = (side ? d[a] + 1 : -2) - g0[a], q = (side ? d[a] - 1 : 0) - g0[a];
      if (p < 0 || p >= n || q < 0 || q >= n)
        continue;
      for (int v = 0; v < n; ++v) {
        const int gv = g0[c] + v;
        if (gv < -1 || gv > d[c])
          continue;
        for (int u = 0; u < n; ++u) {
          const int gu = g0[b] + u;
          if (gu < -1 || gu > d[b])
            continue;
          const int64_t base = u * st[b] + v * st[c];
          s[base + p * st[a]] = -s[base + q * st[a]];
        }
      }
    }
  }
}

int64_t BrickMarchingCubes::Extract(const Voxmap& bone, const std::array<int, 3>& first,
                                    Mesh& out) {
  out.Clear();
  const auto& d = bone.Dims();
  // The brick's cells that exist (-1 .. Dims - 1), in brick-local cell coordinates [lo, hi); their
  // samples are the local samples lo .. hi (box sample = local sample + 1).
  std::array<int, 3> lo, hi, sLo, sHi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, -1 - first[a]);
    hi[a] = std::min(B_, d[a] - first[a]);
    if (lo[a] >= hi[a])
      return 0;
    sLo[a] = first[a] + lo[a];
    sHi[a] = first[a] + hi[a];
  }
  if (!AnyBone(bone, sLo, sHi))
    return 0; // all void: no surface, nothing read
  Load(bone, first);

  // Classify the cells' samples: one bit per sample along x (bit = local x), one mask per row
  // (local y, z); bits outside lo .. hi are 0. Load made them (box x = local x + 1).
  const int n = N_, m = B_ + 1;
  const int64_t sy = n, sz = int64_t(n) * n;
  const float* s = S_.data();
  uint64_t* mask = Mask_.data();
  const uint64_t full = ((uint64_t(2) << hi[0]) - 1) & ~((uint64_t(1) << lo[0]) - 1);
  bool anyAbove = false, anyBelow = false;
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y) {
      const uint64_t bits = (RowBits_[size_t((y + 1) + n * (z + 1))] >> 1) & full;
      mask[y + m * z] = bits;
      anyAbove |= bits != 0;
      anyBelow |= bits != full;
    }
  if (!anyAbove || !anyBelow)
    return 0;           // all void or all bone: no cell straddles the iso
  Convert(bone, first); // the samples' values, for the vertices

  // Every cut edge's vertex, once: edges along x, y, z from each sample (lower end), within the
  // cells. vtkFlyingEdges3D's arithmetic on the padded grid (index p = voxel + 1, origin one voxel
  // before the grid's): the point in index space as a float, then to world, so the points are
  // flying edges' over the whole padded grid bit for bit; the normal is the negated gradient
  // (central differences at the two samples, index space) interpolated along the edge.
  const int64_t st[3] = {1, sy, sz};
  const double h = bone.Spacing();
  const std::array<double, 3> o{bone.Origin()[0] - h, bone.Origin()[1] - h, bone.Origin()[2] - h};
  float* pts = Points_.data();
  float* nrms = Normals_.data();
  int32_t nv = 0;
  auto vertex = [&](int x, int y, int z, int axis) {
    const int64_t s0i = (x + 1) + (y + 1) * sy + (z + 1) * sz, s1i = s0i + st[axis];
    const float v0 = s[s0i], v1 = s[s1i];
    const double t = (Iso_ - v0) / double(v1 - v0);
    const int p[3] = {first[0] + x + 1, first[1] + y + 1, first[2] + z + 1};
    float* xyz = pts + 3 * nv;
    for (int q = 0; q < 3; ++q) {
      const float xi = q == axis ? float(double(p[q]) + t) : float(p[q]);
      xyz[q] = float(o[size_t(q)] + h * double(xi));
    }
    float* nrm = nrms + 3 * nv;
    for (int q = 0; q < 3; ++q) {
      const float g0 = 0.5f * (s[s0i + st[q]] - s[s0i - st[q]]);
      const float g1 = 0.5f * (s[s1i + st[q]] - s[s1i - st[q]]);
      nrm[q] = -float(g0 + t * (g1 - g0));
    }
    vtkMath::Normalize(nrm); // leaves a zero gradient zero
    EdgeVertex_[size_t(3 * s0i + axis)] = nv++;
  };
  const uint64_t xEdges = full & (full >> 1); // edges x .. x + 1 with both ends in lo .. hi
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y) {
      const uint64_t r = mask[y + m * z];
      for (uint64_t c = (r ^ (r >> 1)) & xEdges; c; c &= c - 1)
        vertex(__builtin_ctzll(c), y, z, 0);
      if (y < hi[1])
        for (uint64_t c = r ^ mask[y + 1 + m * z]; c; c &= c - 1)
          vertex(__builtin_ctzll(c), y, z, 1);
      if (z < hi[2])
        for (uint64_t c = r ^ mask[y + m * (z + 1)]; c; c &= c - 1)
          vertex(__builtin_ctzll(c), y, z, 2);
    }

  // The cells' cases (VTK's corner order: (0,0,0), (1,0,0), (1,1,0), (0,1,0), then z + 1) and
  // triangles, for the cells that straddle the iso only (found for a row of cells at once).
  int64_t edgeKey[12];
  for (int e = 0; e < 12; ++e)
    edgeKey[e] =
        3 * (kEdgeCorner[e][0] + sy * kEdgeCorner[e][1] + sz * kEdgeCorner[e][2]) + kEdgeAxis[e];
  const vtkMarchingCubesTriangleCases* cases = vtkMarchingCubesTriangleCases::GetCases();
  const int32_t* ids = EdgeVertex_.data();
  int32_t* tris = Triangles_.data();
  int64_t nt = 0;
  for (int z = lo[2]; z < hi[2]; ++z)
    for (int y = lo[1]; y < hi[1]; ++y) {
      const uint64_t m00 = mask[y + m * z], m10 = mask[y + 1 + m * z], m01 = mask[y + m * (z + 1)],
                     m11 = mask[y + 1 + m * (z + 1)];
      // Cell x straddles the iso when its eight corners (bits x and x + 1 of the four rows)
      // differ: across the rows at column x or x + 1, or along x within one row.
      const uint64_t across = (m00 ^ m10) | (m00 ^ m01) | (m00 ^ m11);
      const uint64_t straddling = (across | (across >> 1) | (m00 ^ (m00 >> 1))) & xEdges;
      const int64_t row = 3 * ((y + 1) * sy + (z + 1) * sz + 1);
      for (uint64_t c = straddling; c; c &= c - 1) {
        const int x = __builtin_ctzll(c);
        const int index = int((m00 >> x) & 1) | int((m00 >> x) & 2) | int((m10 >> x) & 2) << 1 |
                          int((m10 >> x) & 1) << 3 | int((m01 >> x) & 1) << 4 |
                          int((m01 >> x) & 2) << 4 | int((m11 >> x) & 2) << 5 |
                          int((m11 >> x) & 1) << 7;
        const int32_t* cell = ids + row + 3 * x;
        for (const int* e = cases[index].edges; e[0] >= 0; e += 3, nt += 3) {
          tris[nt] = cell[edgeKey[e[0]]];
          tris[nt + 1] = cell[edgeKey[e[1]]];
          tris[nt + 2] = cell[edgeKey[e[2]]];
        }
      }
    }
  out.points.assign(pts, pts + 3 * nv);
  out.normals.assign(nrms, nrms + 3 * nv);
  out.triangles.assign(tris, tris + nt);
  return nt / 3;
}

} // namespace bm
