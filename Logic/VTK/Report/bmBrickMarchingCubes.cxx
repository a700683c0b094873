// bmBrickMarchingCubes.cxx - see bmBrickMarchingCubes.h.
#include "bmBrickMarchingCubes.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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
  if (cells < 2 || cells > 256)
    throw std::invalid_argument("BrickMarchingCubes: cells must be in 2..256");
  if (!(iso > 0.0 && iso < 1.0))
    throw std::invalid_argument("BrickMarchingCubes: iso must be in (0, 1)");
  const size_t n = size_t(N_) * N_ * N_;
  S_.assign(n, 0.0f);
  Above_.assign(n, 0);
  EdgeVertex_.assign(3 * n, 0);
  EdgeStamp_.assign(3 * n, 0);
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

void BrickMarchingCubes::Load(const Voxmap& bone, const std::array<int, 3>& first) {
  const auto& d = bone.Dims();
  const int n = N_;
  const std::array<int, 3> g0{first[0] - 1, first[1] - 1, first[2] - 1}; // box sample 0, voxels
  float* s = S_.data();
  constexpr float kScale = 1.0f / float(Voxmap::kFull); // a power of two: exact
  // The box's samples in the grid; void elsewhere.
  const int xLo = std::clamp(-g0[0], 0, n), xHi = std::clamp(d[0] - g0[0], 0, n);
  for (int z = 0; z < n; ++z) {
    const int gz = g0[2] + z;
    for (int y = 0; y < n; ++y) {
      const int gy = g0[1] + y;
      float* row = s + int64_t(n) * (y + int64_t(n) * z);
      if (gz < 0 || gz >= d[2] || gy < 0 || gy >= d[1] || xLo >= xHi) {
        std::fill(row, row + n, 0.0f);
        continue;
      }
      std::fill(row, row + xLo, 0.0f);
      std::fill(row + xHi, row + n, 0.0f);
      const int64_t base = bone.Index(0, gy, gz) + g0[0];
      for (int x = xLo; x < xHi; ++x) {
        const Voxmap::Fill f = bone.LoadFill(base + x);
        row[x] = f <= 0 ? 0.0f : float(f) * kScale;
      }
    }
  }
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
  // The brick's cells that exist (-1 .. Dims - 1), in brick-local cell coordinates [lo, hi).
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

  // Classify the cells' samples (box coordinates: local sample l is box sample l + 1).
  const int n = N_;
  const int64_t sy = n, sz = int64_t(n) * n;
  const float* s = S_.data();
  uint8_t* above = Above_.data();
  bool anyAbove = false, anyBelow = false;
  for (int z = lo[2] + 1; z <= hi[2] + 1; ++z)
    for (int y = lo[1] + 1; y <= hi[1] + 1; ++y) {
      const int64_t row = sy * y + sz * z;
      for (int x = lo[0] + 1; x <= hi[0] + 1; ++x) {
        const bool up = double(s[row + x]) >= Iso_;
        above[row + x] = uint8_t(up);
        anyAbove |= up;
        anyBelow |= !up;
      }
    }
  if (!anyAbove || !anyBelow)
    return 0; // all void or all bone: no cell straddles the iso

  if (++Stamp_ == 0) { // wrapped: forget every edge
    std::fill(EdgeStamp_.begin(), EdgeStamp_.end(), 0u);
    Stamp_ = 1;
  }
  const int64_t st[3] = {1, sy, sz};
  int64_t edgeOffset[12];
  for (int e = 0; e < 12; ++e)
    edgeOffset[e] = kEdgeCorner[e][0] + sy * kEdgeCorner[e][1] + sz * kEdgeCorner[e][2];
  const double h = bone.Spacing();
  const auto& origin = bone.Origin();
  const vtkMarchingCubesTriangleCases* cases = vtkMarchingCubesTriangleCases::GetCases();

  // The vertex on edge e of the cell whose lower corner is box sample a (grid position g, voxel
  // coordinates), made the first time the brick uses that edge.
  auto vertex = [&](int64_t a, const std::array<int, 3>& g, int e) -> int32_t {
    const int64_t s0i = a + edgeOffset[e];
    const int axis = kEdgeAxis[e];
    const int64_t key = 3 * s0i + axis;
    if (EdgeStamp_[size_t(key)] == Stamp_)
      return EdgeVertex_[size_t(key)];
    const int64_t s1i = s0i + st[axis];
    const float v0 = s[s0i], v1 = s[s1i];
    const double t = (Iso_ - v0) / double(v1 - v0);
    const int32_t id = int32_t(out.points.size() / 3);
    // vtkFlyingEdges3D's arithmetic on the padded grid (index p = voxel + 1, origin one voxel
    // before the grid's): the point in index space as a float, then to world: the same points, bit
    // for bit, as flying edges over the whole padded grid.
    for (int q = 0; q < 3; ++q) {
      const int p = g[q] + kEdgeCorner[e][q] + 1;
      const float x = q == axis ? float(double(p) + t) : float(p);
      out.points.push_back(float((origin[q] - h) + h * double(x)));
    }
    // Gradients at the two samples (central differences, index space), interpolated; the
    // normal points down the fill, out of the bone.
    float nrm[3];
    for (int q = 0; q < 3; ++q) {
      const float g0 = 0.5f * (s[s0i + st[q]] - s[s0i - st[q]]);
      const float g1 = 0.5f * (s[s1i + st[q]] - s[s1i - st[q]]);
      nrm[q] = -float(g0 + t * (g1 - g0));
    }
    vtkMath::Normalize(nrm); // leaves a zero gradient zero
    out.normals.insert(out.normals.end(), nrm, nrm + 3);
    EdgeStamp_[size_t(key)] = Stamp_;
    EdgeVertex_[size_t(key)] = id;
    return id;
  };

  for (int z = lo[2]; z < hi[2]; ++z)
    for (int y = lo[1]; y < hi[1]; ++y) {
      const int64_t row = (y + 1) * sy + (z + 1) * sz + 1;
      for (int x = lo[0]; x < hi[0]; ++x) {
        const int64_t a = row + x;
        const uint8_t* c = above + a;
        const int index = c[0] | c[1] << 1 | c[1 + sy] << 2 | c[sy] << 3 | c[sz] << 4 |
                          c[1 + sz] << 5 | c[1 + sy + sz] << 6 | c[sy + sz] << 7;
        if (index == 0 || index == 255)
          continue;
        const std::array<int, 3> g{first[0] + x, first[1] + y, first[2] + z};
        for (const int* e = cases[index].edges; e[0] >= 0; e += 3) {
          const int32_t p0 = vertex(a, g, e[0]), p1 = vertex(a, g, e[1]), p2 = vertex(a, g, e[2]);
          out.triangles.push_back(p0);
          out.triangles.push_back(p1);
          out.triangles.push_back(p2);
        }
      }
    }
  return out.NumTriangles();
}

} // namespace bm
