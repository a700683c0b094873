// TestBrickMarchingCubes.cxx - the per-brick marching cubes (bmBrickMarchingCubes.h), through
// BoneSurface and alone, against vtkFlyingEdges3D run once over the whole padded grid: the same
// points, triangles (orientation included) and normals, the same area and enclosed volume, a
// closed surface; after cuts, the incrementally patched surface is the fresh one.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticPointLocator.h>

#include "bmBoneSurface.h"
#include "bmBrickMarchingCubes.h"
#include "bmTestFlyingEdges.h"
#include "bmVoxmap.h"

namespace {

constexpr double kH = 0.2; // voxel spacing, mm
const std::array<int, 3> kDims{45, 38, 33};
const std::array<double, 3> kOrigin{-3.0, 1.0, 2.0};

/// Fills this close to the iso (0.5) are kept out: their vertices would lie within float
/// rounding of a sample, on top of their neighbours', and points could not be matched one to one.
constexpr bm::Voxmap::Fill kHalf = bm::Voxmap::kFull / 2, kMargin = 1024;

/// Partial-volume fill of a signed distance d (mm, > 0 inside), kMargin off the iso.
bm::Voxmap::Fill FillOf(double d) {
  const auto f = bm::Voxmap::Fill(std::clamp(0.5 + d / kH, 0.0, 1.0) * bm::Voxmap::kFull);
  return std::abs(f - kHalf) >= kMargin ? f : f >= kHalf ? kHalf + kMargin : kHalf - kMargin;
}

/// A ball of bone on a slab that reaches the grid's x = 0 face, with two bars reaching the +y and
/// +z faces and one through the +x face: the surface crosses brick faces everywhere and closes on
/// the padding on five of the grid's faces.
bm::Voxmap MakePhantom() {
  bm::Voxmap v(kDims, kH, kOrigin);
  const std::array<double, 3> c{-3.0 + 24.3 * kH, 1.0 + 19.2 * kH, 2.0 + 16.4 * kH};
  for (int k = 0; k < kDims[2]; ++k)
    for (int j = 0; j < kDims[1]; ++j)
      for (int i = 0; i < kDims[0]; ++i) {
        const auto p = v.GridToWorld({double(i), double(j), double(k)});
        const double ball =
            4.3 - std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                            (p[2] - c[2]) * (p[2] - c[2]));
        const double slab =
            std::min({(-3.0 + 11.7 * kH) - p[0], p[1] - (1.0 + 6.3 * kH), (1.0 + 30.4 * kH) - p[1],
                      p[2] - (2.0 + 5.2 * kH), (2.0 + 27.6 * kH) - p[2]});
        // Bars: along y at (x, z) near (30, 8); along z at (x, y) near (12, 30); along x at
        // (y, z) near (8, 28). Round cross-sections of radius 1.1 mm.
        const double barY = 1.1 - std::hypot(p[0] - (-3.0 + 30.5 * kH), p[2] - (2.0 + 8.3 * kH));
        const double barZ = 1.1 - std::hypot(p[0] - (-3.0 + 12.4 * kH), p[1] - (1.0 + 30.1 * kH));
        const double barX = 1.1 - std::hypot(p[1] - (1.0 + 8.2 * kH), p[2] - (2.0 + 27.7 * kH));
        const double barYc = std::min(barY, p[1] - (1.0 + 18 * kH)); // from the ball to +y
        const double barZc = std::min(barZ, p[2] - (2.0 + 16 * kH)); // from the ball to +z
        v.SetFill(v.Index(i, j, k), FillOf(std::max({ball, slab, barYc, barZc, barX})));
      }
  return v;
}

using Tri = std::array<vtkIdType, 3>;

std::vector<Tri> TrianglesOf(vtkPolyData* pd) {
  std::vector<Tri> out;
  vtkCellArray* polys = pd->GetPolys();
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < polys->GetNumberOfCells(); ++c) {
    polys->GetCellAtId(c, ids);
    EXPECT_EQ(ids->GetNumberOfIds(), 3);
    out.push_back({ids->GetId(0), ids->GetId(1), ids->GetId(2)});
  }
  return out;
}

/// Area (mm^2) and enclosed volume (mm^3, by the divergence theorem: > 0 when the triangles wind
/// counter-clockwise seen from outside) of a triangle surface, in double.
std::pair<double, double> AreaAndVolume(vtkPolyData* pd) {
  double area = 0, volume = 0;
  for (const Tri& t : TrianglesOf(pd)) {
    double a[3], b[3], c[3];
    pd->GetPoint(t[0], a);
    pd->GetPoint(t[1], b);
    pd->GetPoint(t[2], c);
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2],
                 z = u[0] * w[1] - u[1] * w[0];
    area += 0.5 * std::sqrt(x * x + y * y + z * z);
    volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
               a[2] * (b[0] * c[1] - b[1] * c[0])) /
              6.0;
  }
  return {area, volume};
}

/// A triangle started at its smallest id, orientation kept.
Tri Canonical(Tri t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

/// Every edge of the surface, its points merged by position (`merged`), is used once in each
/// direction: closed, no cracks, consistently oriented. Returns the number of bad edges.
int64_t BadEdges(const std::vector<Tri>& triangles) {
  std::map<std::pair<vtkIdType, vtkIdType>, int> directed;
  for (const Tri& t : triangles) {
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) << "degenerate triangle";
    for (int q = 0; q < 3; ++q)
      ++directed[{t[size_t(q)], t[size_t((q + 1) % 3)]}];
  }
  int64_t bad = 0;
  for (const auto& [e, n] : directed) {
    const auto back = directed.find({e.second, e.first});
    if (n != 1 || back == directed.end() || back->second != 1)
      ++bad;
  }
  return bad;
}

/// Checks that `ours` (bricks: points on brick faces duplicated) is `ref` (one flying-edges run):
/// every point of ours is a point of ref (to 1e-5 mm) with the same normal (to 1e-5), every
/// point of ref is one of ours, the triangles are the same with the same orientation, area and
/// enclosed volume agree (relative 1e-9), and both are closed.
void ExpectFlyingEdgesSurface(vtkPolyData* ours, vtkPolyData* ref) {
  ASSERT_GT(ref->GetNumberOfCells(), 1000);
  ASSERT_EQ(ours->GetNumberOfCells(), ref->GetNumberOfCells());
  vtkDataArray* refNormals = ref->GetPointData()->GetNormals();
  vtkDataArray* ourNormals = ours->GetPointData()->GetNormals();
  ASSERT_NE(refNormals, nullptr);
  ASSERT_NE(ourNormals, nullptr);
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(ref);
  locator->BuildLocator();
  // Our points onto ref's.
  const std::vector<Tri> ourTris = TrianglesOf(ours);
  std::vector<char> used(size_t(ours->GetNumberOfPoints()), 0);
  for (const Tri& t : ourTris)
    for (vtkIdType p : t)
      used[size_t(p)] = 1;
  std::vector<vtkIdType> toRef(size_t(ours->GetNumberOfPoints()), -1);
  std::vector<char> hit(size_t(ref->GetNumberOfPoints()), 0);
  double worstPoint = 0, worstNormal = 0;
  for (vtkIdType p = 0; p < ours->GetNumberOfPoints(); ++p) {
    if (!used[size_t(p)])
      continue; // a free place in the patched arrays
    double x[3], y[3], n[3], m[3];
    ours->GetPoint(p, x);
    const vtkIdType r = locator->FindClosestPoint(x);
    ref->GetPoint(r, y);
    worstPoint =
        std::max({worstPoint, std::abs(x[0] - y[0]), std::abs(x[1] - y[1]), std::abs(x[2] - y[2])});
    ourNormals->GetTuple(p, n);
    refNormals->GetTuple(r, m);
    worstNormal = std::max(
        {worstNormal, std::abs(n[0] - m[0]), std::abs(n[1] - m[1]), std::abs(n[2] - m[2])});
    toRef[size_t(p)] = r;
    hit[size_t(r)] = 1;
  }
  EXPECT_LE(worstPoint, 1e-5) << "a point is not one of flying edges' (mm)";
  EXPECT_LE(worstNormal, 1e-5) << "a normal differs from flying edges'";
  EXPECT_EQ(std::count(hit.begin(), hit.end(), 0), 0) << "flying edges' points we do not make";
  // The triangles, in ref's point ids.
  std::vector<Tri> mapped, refTris = TrianglesOf(ref);
  for (const Tri& t : ourTris)
    mapped.push_back(Canonical({toRef[size_t(t[0])], toRef[size_t(t[1])], toRef[size_t(t[2])]}));
  for (Tri& t : refTris)
    t = Canonical(t);
  std::sort(mapped.begin(), mapped.end());
  std::sort(refTris.begin(), refTris.end());
  EXPECT_TRUE(mapped == refTris) << "the triangles (or their orientation) differ";
  const auto [area, volume] = AreaAndVolume(ours);
  const auto [refArea, refVolume] = AreaAndVolume(ref);
  EXPECT_NEAR(area, refArea, 1e-9 * refArea);
  EXPECT_NEAR(volume, refVolume, 1e-9 * std::abs(refVolume));
  EXPECT_EQ(BadEdges(mapped), 0) << "ours, merged: not closed";
  EXPECT_EQ(BadEdges(refTris), 0) << "flying edges': not closed";
}

/// The ids of a surface's triangles mapped to positions, for exact comparison of two outputs of
/// BoneSurface (the same code, so the same floats).
std::vector<std::array<float, 18>> PointsAndNormals(vtkPolyData* pd) {
  std::vector<std::array<float, 18>> out;
  vtkDataArray* normals = pd->GetPointData()->GetNormals();
  for (Tri t : TrianglesOf(pd)) {
    // Start at the smallest point (by position), keeping the orientation.
    std::array<std::array<float, 6>, 3> v;
    for (int q = 0; q < 3; ++q) {
      double x[3], n[3];
      pd->GetPoint(t[size_t(q)], x);
      normals->GetTuple(t[size_t(q)], n);
      v[size_t(q)] = {float(x[0]), float(x[1]), float(x[2]), float(n[0]), float(n[1]), float(n[2])};
    }
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
    std::array<float, 18> r;
    for (size_t q = 0; q < 3; ++q)
      std::copy(v[q].begin(), v[q].end(), r.begin() + 6 * q);
    out.push_back(r);
  }
  std::sort(out.begin(), out.end());
  return out;
}

} // namespace

TEST(BrickMarchingCubes, BricksMakeFlyingEdgesSurfaceOfTheWholeGrid) {
  const bm::Voxmap bone = MakePhantom();
  const vtkSmartPointer<vtkPolyData> ref = bm::test::WholeGridFlyingEdges(bone, true);
  // The enclosed volume is the bone's, roughly (partial-volume fills), and positive: the
  // triangles wind counter-clockwise seen from the void, as the normals point.
  const double volume = AreaAndVolume(ref).second;
  EXPECT_NEAR(volume, bone.BoneVolume(), 0.03 * bone.BoneVolume());
  for (int brick : {8, 5, 32}) {
    SCOPED_TRACE("bricks of " + std::to_string(brick));
    bm::BoneSurface surface(brick);
    surface.Update(bone);
    ExpectFlyingEdgesSurface(surface.GetOutput(), ref);
  }
}

TEST(BrickMarchingCubes, NormalsPointOutOfTheBone) {
  const bm::Voxmap bone = MakePhantom();
  bm::BoneSurface surface;
  surface.Update(bone);
  vtkPolyData* pd = surface.GetOutput();
  vtkDataArray* normals = pd->GetPointData()->GetNormals();
  // Along each normal the fill falls: a step out of the bone lands in emptier voxels.
  int64_t checked = 0, wrong = 0;
  for (vtkIdType p = 0; p < pd->GetNumberOfPoints(); p += 7) {
    double x[3], n[3];
    pd->GetPoint(p, x);
    normals->GetTuple(p, n);
    EXPECT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-6);
    auto fraction = [&](double s) {
      std::array<int, 3> ijk;
      const std::array<double, 3> y{x[0] + s * n[0], x[1] + s * n[1], x[2] + s * n[2]};
      return bone.VoxelAt(y, ijk) ? bone.Fraction(bone.Index(ijk[0], ijk[1], ijk[2])) : 0.0;
    };
    ++checked;
    wrong += fraction(1.5 * kH) > fraction(-1.5 * kH);
  }
  EXPECT_GT(checked, 100);
  EXPECT_LT(wrong, checked / 50) << "normals pointing into the bone";
}

TEST(BrickMarchingCubes, EmptyFullAndOutsideBricksMakeNothing) {
  const bm::Voxmap bone = MakePhantom();
  bm::BrickMarchingCubes cubes;
  bm::BrickMarchingCubes::Mesh mesh;
  // Every brick of 8^3 cells at a few offsets, classified from the fills: all samples of its
  // cells bone, all void, or both (then a cell straddles the iso: triangles, inside its cells).
  auto sample = [&](int i, int j, int k) {
    return bone.Contains(i, j, k) ? bone.Fraction(bone.Index(i, j, k)) : 0.0;
  };
  int full = 0, empty = 0, mixed = 0;
  for (int off : {-2, 0, 3})
    for (int bk = off; bk < kDims[2]; bk += 8)
      for (int bj = off; bj < kDims[1]; bj += 8)
        for (int bi = off; bi < kDims[0]; bi += 8) {
          const std::array<int, 3> first{bi, bj, bk};
          bool above = false, below = false;
          for (int k = std::max(bk, -1); k <= std::min(bk + 8, kDims[2]); ++k)
            for (int j = std::max(bj, -1); j <= std::min(bj + 8, kDims[1]); ++j)
              for (int i = std::max(bi, -1); i <= std::min(bi + 8, kDims[0]); ++i)
                (sample(i, j, k) >= 0.5 ? above : below) = true;
          mesh.triangles = {0, 0, 0}; // replaced by Extract
          const int64_t n = cubes.Extract(bone, first, mesh);
          EXPECT_EQ(n, mesh.NumTriangles());
          if (!(above && below)) {
            ++(above ? full : empty);
            EXPECT_EQ(n, 0) << "brick at " << bi << " " << bj << " " << bk;
            continue;
          }
          ++mixed;
          EXPECT_GT(n, 0) << "brick at " << bi << " " << bj << " " << bk;
          for (int32_t id : mesh.triangles)
            ASSERT_TRUE(id >= 0 && id < mesh.NumPoints());
          for (int64_t p = 0; p < mesh.NumPoints(); ++p) {
            const auto g =
                bone.WorldToGrid({mesh.points[size_t(3 * p)], mesh.points[size_t(3 * p + 1)],
                                  mesh.points[size_t(3 * p + 2)]});
            for (size_t a = 0; a < 3; ++a) {
              EXPECT_GE(g[a], std::max(first[a], -1) - 1e-4);
              EXPECT_LE(g[a], std::min(first[a] + 8, kDims[a]) + 1e-4);
            }
          }
        }
  EXPECT_GT(full, 0);
  EXPECT_GT(empty, 0);
  EXPECT_GT(mixed, 20);
  // Wholly outside the padded grid.
  mesh.triangles = {0, 0, 0};
  EXPECT_EQ(cubes.Extract(bone, {-12, 0, 0}, mesh), 0);
  EXPECT_EQ(mesh.NumTriangles(), 0);
  EXPECT_EQ(cubes.Extract(bone, {0, 0, kDims[2]}, mesh), 0);
}

TEST(BrickMarchingCubes, IncrementalAfterCutsIsFlyingEdgesAndTheFreshSurface) {
  bm::Voxmap bone = MakePhantom();
  bm::BoneSurface live; // bricks of 8
  live.Update(bone);
  // Passes of a ball tool: over the ball's top, through the slab and the +z bar (reaching the
  // grid's face), and one that cuts a tunnel through the ball; each update patches the output.
  const std::array<double, 3> top{-3.0 + 24.3 * kH, 1.0 + 19.2 * kH, 2.0 + 16.4 * kH + 4.0};
  for (int s = 0; s < 12; ++s) {
    bm::test::CutBall(bone, {top[0] - 1.2 + 0.2 * s, top[1] + 0.05 * s, top[2]}, 1.3, 0.3, kH,
                      kMargin);
    bm::test::CutBall(bone, {-3.0 + (2 + s) * kH, 1.0 + 20 * kH, 2.0 + 27.0 * kH}, 1.0, 0.5, kH,
                      kMargin);
    bm::test::CutBall(bone, {-3.0 + 12.4 * kH, 1.0 + 30.1 * kH, 2.0 + (20 + s) * kH}, 0.9, 1.0, kH,
                      kMargin);
    const int n = live.Update(bone);
    EXPECT_GT(n, 0) << "step " << s;
    EXPECT_LT(n, live.NumBricks() / 2) << "step " << s << ": only the cut's bricks";
    if (s % 4 == 3) {
      SCOPED_TRACE("after step " + std::to_string(s));
      ExpectFlyingEdgesSurface(live.GetOutput(), bm::test::WholeGridFlyingEdges(bone, true));
    }
  }
  for (int s = 0; s < 25; ++s)
    bm::test::CutBall(bone, {top[0], top[1], top[2] - 0.35 * s}, 0.8, 1.0, kH,
                      kMargin); // a tunnel down through the ball
  live.Update(bone);
  ExpectFlyingEdgesSurface(live.GetOutput(), bm::test::WholeGridFlyingEdges(bone, true));
  bm::BoneSurface fresh;
  fresh.Update(bone);
  EXPECT_TRUE(PointsAndNormals(live.GetOutput()) == PointsAndNormals(fresh.GetOutput()))
      << "the patched surface's triangles, points or normals differ from a fresh extraction's";
}

TEST(BrickMarchingCubes, GrowingSurfaceIsCopiedIntoLargerArraysNotRewritten) {
  // Tunnels drilled through the bone add surface until the output's arrays must grow: they are
  // copied into larger ones and patched (not rewritten from every brick), and stay right.
  bm::Voxmap bone = MakePhantom();
  bm::BoneSurface live;
  live.Update(bone);
  vtkDataArray* first = live.GetOutput()->GetPoints()->GetData();
  bool grew = false;
  for (int t = 0; t < 40 && !grew; ++t) {
    const double y = 1.0 + (8 + 3 * (t % 8)) * kH, z = 2.0 + (8 + 3 * (t / 8)) * kH;
    for (int s = 0; s < 20; ++s)
      bm::test::CutBall(bone, {-3.0 + (14 + 1.5 * s) * kH, y, z}, 0.25, 1.0, kH, kMargin);
    live.Update(bone);
    EXPECT_LT(live.LastUpdate().rewrittenTriangles, live.GetOutput()->GetNumberOfCells())
        << "tunnel " << t << ": patched, not rewritten";
    grew = live.GetOutput()->GetPoints()->GetData() != first;
  }
  ASSERT_TRUE(grew) << "the tunnels did not grow the arrays: the test needs more of them";
  bm::test::CutBall(bone, {-3.0 + 24 * kH, 1.0 + 19 * kH, 2.0 + 16 * kH}, 0.6, 1.0, kH, kMargin);
  live.Update(bone);
  ExpectFlyingEdgesSurface(live.GetOutput(), bm::test::WholeGridFlyingEdges(bone, true));
  bm::BoneSurface fresh;
  fresh.Update(bone);
  EXPECT_TRUE(PointsAndNormals(live.GetOutput()) == PointsAndNormals(fresh.GetOutput()));
}
