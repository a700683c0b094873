// TestBoneSurface.cxx - the incremental cut-bone surface (bmBoneSurface.h) equals a from-scratch
// extraction after cuts: made between updates, made by another thread during updates, and caught
// up over several time-budgeted updates.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include "bmBoneSurface.h"
#include "bmTestFlyingEdges.h"
#include "bmVoxmap.h"

namespace {

constexpr double kH = 0.2; // voxel spacing, mm

/// A ball of bone joined to a slab that reaches the grid's x = 0 face, with partial-volume fills
/// (a smooth iso-surface, not a staircase).
bm::Voxmap MakeBone() {
  bm::Voxmap v({45, 38, 33}, kH, {-3.0, 1.0, 2.0});
  const std::array<double, 3> c{-3.0 + 24 * kH, 1.0 + 19 * kH, 2.0 + 16 * kH};
  for (int k = 0; k < 33; ++k)
    for (int j = 0; j < 38; ++j)
      for (int i = 0; i < 45; ++i) {
        const auto p = v.GridToWorld({double(i), double(j), double(k)});
        const double ball =
            5.0 - std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                            (p[2] - c[2]) * (p[2] - c[2]));
        const double slab =
            std::min({(-3.0 + 12 * kH) - p[0], p[1] - (1.0 + 6 * kH), (1.0 + 30 * kH) - p[1],
                      p[2] - (2.0 + 5 * kH), (2.0 + 27 * kH) - p[2]});
        const double s = std::max(ball, slab) / kH; // signed distance in voxels, > 0 inside
        v.SetFill(v.Index(i, j, k),
                  bm::Voxmap::Fill(std::clamp(0.5 + s, 0.0, 1.0) * bm::Voxmap::kFull));
      }
  return v;
}

/// The tool's centre at step s of a pass across the ball's top.
std::array<double, 3> ToolAt(int s) {
  return {-3.0 + (18 + s) * kH, 1.0 + 19 * kH, 2.0 + 16 * kH + 4.6};
}

using Triangle = std::array<float, 9>;

/// The surface's triangles as vertex coordinates, each started at its smallest vertex (keeping
/// the orientation), sorted: equal lists mean the same triangles wherever they sit in the arrays.
std::vector<Triangle> Triangles(vtkPolyData* pd) {
  std::vector<Triangle> out;
  vtkCellArray* polys = pd->GetPolys();
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < polys->GetNumberOfCells(); ++c) {
    polys->GetCellAtId(c, ids);
    EXPECT_EQ(ids->GetNumberOfIds(), 3);
    std::array<std::array<float, 3>, 3> v;
    for (int q = 0; q < 3; ++q) {
      double x[3];
      pd->GetPoint(ids->GetId(q), x);
      v[size_t(q)] = {float(x[0]), float(x[1]), float(x[2])};
    }
    const size_t first = size_t(std::min_element(v.begin(), v.end()) - v.begin());
    Triangle t;
    for (size_t q = 0; q < 3; ++q)
      for (size_t a = 0; a < 3; ++a)
        t[3 * q + a] = v[(first + q) % 3][a];
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

double Area(vtkPolyData* pd) {
  double area = 0;
  vtkCellArray* polys = pd->GetPolys();
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < polys->GetNumberOfCells(); ++c) {
    polys->GetCellAtId(c, ids);
    double a[3], b[3], d[3];
    pd->GetPoint(ids->GetId(0), a);
    pd->GetPoint(ids->GetId(1), b);
    pd->GetPoint(ids->GetId(2), d);
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    const double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2],
                 z = u[0] * w[1] - u[1] * w[0];
    area += 0.5 * std::sqrt(x * x + y * y + z * z);
  }
  return area;
}

void ExpectSameSurface(vtkPolyData* live, const bm::Voxmap& bone, int brick) {
  bm::BoneSurface fresh(brick);
  fresh.Update(bone);
  ASSERT_GT(fresh.GetOutput()->GetNumberOfCells(), 1000);
  EXPECT_EQ(live->GetNumberOfCells(), fresh.GetOutput()->GetNumberOfCells());
  EXPECT_TRUE(Triangles(live) == Triangles(fresh.GetOutput()))
      << "the incremental surface's triangles differ from a fresh extraction's";
  // Against one filter over the whole grid: the bricks add up to it (same triangles, the points
  // computed from other origins: equal to float rounding).
  vtkSmartPointer<vtkPolyData> whole = bm::test::WholeGridFlyingEdges(bone, false);
  EXPECT_EQ(live->GetNumberOfCells(), whole->GetNumberOfCells());
  EXPECT_NEAR(Area(live), Area(whole), 1e-5 * Area(whole));
  ASSERT_NE(live->GetPointData()->GetNormals(), nullptr);
  EXPECT_EQ(live->GetPointData()->GetNormals()->GetNumberOfTuples(), live->GetNumberOfPoints());
}

/// Takes `units` of fill from voxel (i, j, k) the way the CPU engine does (RemoveOwned, then
/// MarkBricksChanged).
void RemoveOwnedAt(bm::Voxmap& v, int i, int j, int k, bm::Voxmap::Fill units) {
  std::vector<int64_t> touched;
  const int64_t idx = v.Index(i, j, k);
  const bm::Voxmap::RemovalRequest r{idx, units, int32_t(v.BrickOfVoxel(idx))};
  v.RemoveOwned(&r, 1, touched);
  v.MarkBricksChanged(touched);
}

} // namespace

TEST(BoneSurface, IncrementalEqualsFromScratchAfterCuts) {
  bm::Voxmap bone = MakeBone();
  bm::BoneSurface live(8);
  const int first = live.Update(bone);
  EXPECT_EQ(first, live.NumBricks()) << "the first update extracts everything";
  const double before = Area(live.GetOutput());
  EXPECT_EQ(live.Update(bone), 0) << "nothing changed";
  for (int s = 0; s < 10; ++s) {
    bm::test::CutBall(bone, ToolAt(s), 1.5, 0.35, kH);
    const int n = live.Update(bone);
    EXPECT_GT(n, 0) << "step " << s;
    EXPECT_LT(n, live.NumBricks() / 4) << "step " << s << ": only the cut's bricks";
    EXPECT_LT(live.LastUpdate().rewrittenTriangles, live.GetOutput()->GetNumberOfCells())
        << "step " << s << ": the output is patched, not rebuilt";
  }
  EXPECT_NE(Area(live.GetOutput()), before);
  ExpectSameSurface(live.GetOutput(), bone, 8);
}

TEST(BoneSurface, ManualMarksAndBrickSizes) {
  // Writes behind the voxmap's back (bulk writes, then RebuildOccupancy) mark everything; the
  // result does not depend on the brick size beyond float rounding.
  bm::Voxmap bone = MakeBone();
  bm::BoneSurface a(16), b(5);
  a.Update(bone);
  b.Update(bone);
  bm::test::CutBall(bone, ToolAt(3), 2.0, 1.0, kH);
  a.Update(bone);
  b.Update(bone);
  EXPECT_EQ(a.GetOutput()->GetNumberOfCells(), b.GetOutput()->GetNumberOfCells());
  EXPECT_NEAR(Area(a.GetOutput()), Area(b.GetOutput()), 1e-5 * Area(a.GetOutput()));
  std::fill(bone.MutableFill(), bone.MutableFill() + bone.NumVoxels() / 2, 0);
  bone.RebuildOccupancy();
  EXPECT_EQ(a.Update(bone), a.NumBricks());
  ExpectSameSurface(a.GetOutput(), bone, 16);
}

TEST(BoneSurface, TimeBudgetCatchesUp) {
  bm::Voxmap bone = MakeBone();
  bm::BoneSurface live(8);
  live.Update(bone);
  live.SetTimeBudgetMs(1e-6); // one brick per update
  bm::test::CutBall(bone, ToolAt(0), 2.0, 0.5, kH);
  EXPECT_EQ(live.Update(bone), 1);
  const int pending = live.LastUpdate().pending;
  EXPECT_GT(pending, 3);
  int updates = 1;
  while (live.LastUpdate().pending > 0 && updates < 10000) {
    EXPECT_EQ(live.Update(bone), 1);
    ++updates;
  }
  EXPECT_EQ(updates, pending + 1);
  ExpectSameSurface(live.GetOutput(), bone, 8);
}

TEST(BoneSurface, UpdatesWhileAnotherThreadCuts) {
  // The live view's case: the haptic thread cuts while the view updates, neither waits. Once
  // the cutting stops, one more update must give the surface of the final bone.
  bm::Voxmap bone = MakeBone();
  bm::BoneSurface live(8);
  live.Update(bone);
  std::atomic<bool> done{false};
  std::atomic<int> updates{0};
  std::thread cutter([&] {
    for (int s = 0; s < 16; ++s) {
      while (updates.load() < s) // keep the two interleaved on a busy machine
        std::this_thread::yield();
      bm::test::CutBall(bone, ToolAt(s), 1.5, 0.2, kH);
    }
    done.store(true);
  });
  while (!done.load()) {
    live.Update(bone);
    updates.fetch_add(1);
  }
  cutter.join();
  live.Update(bone);
  EXPECT_GE(updates.load(), 16);
  ExpectSameSurface(live.GetOutput(), bone, 8);
}

TEST(BoneSurface, OwnedRemovalsRedoOnlyTheBricksTheyReach) {
  // The CPU engine's removals say where in its brick each changed voxel lay: a voxel below a
  // voxmap brick's upper three layers on every axis reaches one brick of ours, one in them on
  // every axis eight (bricks of 8, the voxmap's).
  bm::Voxmap bone = MakeBone();
  bm::BoneSurface live(8);
  live.Update(bone);
  RemoveOwnedAt(bone, 26, 18, 18, bm::Voxmap::kFull / 4); // local (2, 2, 2), inside the ball
  EXPECT_EQ(live.Update(bone), 1);
  RemoveOwnedAt(bone, 30, 22, 22, bm::Voxmap::kFull / 4); // local (6, 6, 6)
  EXPECT_EQ(live.Update(bone), 8);
  RemoveOwnedAt(bone, 30, 18, 18, bm::Voxmap::kFull / 4); // local (6, 2, 2)
  EXPECT_EQ(live.Update(bone), 2);
  RemoveOwnedAt(bone, 26, 18, 18, bm::Voxmap::kFull / 4);
  RemoveOwnedAt(bone, 26, 22, 18, bm::Voxmap::kFull / 4); // local (2, 6, 2): the same brick
  EXPECT_EQ(live.Update(bone), 2);
  ExpectSameSurface(live.GetOutput(), bone, 8);
}

TEST(BoneSurface, TwoReadersOfOneVoxmapBothStayRight) {
  // Holes cut at random through the engine's removal path while two surfaces update in random
  // turns: a reader that finds the reach taken by the other (or changes from before the other
  // looked) must redo all eight bricks, and both must end equal to a fresh extraction.
  bm::Voxmap bone = MakeBone();
  bm::BoneSurface a(8), b(8);
  a.Update(bone);
  b.Update(bone);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> x(0, 44), y(0, 37), z(0, 32), turn(0, 3);
  std::uniform_int_distribution<int> units(bm::Voxmap::kFull / 8, bm::Voxmap::kFull);
  for (int round = 0; round < 60; ++round) {
    for (int c = 0; c < 25; ++c)
      RemoveOwnedAt(bone, x(rng), y(rng), z(rng), units(rng));
    const int t = turn(rng);
    if (t != 1)
      a.Update(bone);
    if (t != 0)
      b.Update(bone);
  }
  a.Update(bone);
  b.Update(bone);
  ExpectSameSurface(a.GetOutput(), bone, 8);
  ExpectSameSurface(b.GetOutput(), bone, 8);
}

TEST(BoneSurface, ACutThatOnlyMovesVerticesPatchesThemInPlace) {
  // A voxel on the surface that keeps its side of the iso moves the vertices on its cut edges but
  // changes no cell's case: its bricks keep their triangles and places, only points and normals
  // are rewritten. A voxel taken across the iso changes triangles: those bricks are re-added.
  bm::Voxmap bone = MakeBone();
  bm::BoneSurface live(8);
  live.Update(bone);
  const bm::Voxmap::Fill iso = bm::Voxmap::kFull / 2;
  int64_t surface = -1;
  for (int k = 2; k < 30 && surface < 0; ++k)
    for (int j = 2; j < 35 && surface < 0; ++j)
      for (int i = 2; i < 42 && surface < 0; ++i) {
        const int64_t at = bone.Index(i, j, k);
        if (bone.GetFill(at) > iso + bm::Voxmap::kFull / 4 && bone.GetFill(at + 1) < iso)
          surface = at;
      }
  ASSERT_GE(surface, 0);
  const auto ijk = [&](int64_t at) {
    return std::array<int, 3>{int(at % 45), int(at / 45 % 38), int(at / (45 * 38))};
  };
  const auto c = ijk(surface);
  const double before = Area(live.GetOutput());
  RemoveOwnedAt(bone, c[0], c[1], c[2], bm::Voxmap::kFull / 8); // stays above the iso
  const int n = live.Update(bone);
  EXPECT_GT(n, 0);
  EXPECT_EQ(live.LastUpdate().patched, n) << "no case changed: every brick patched in place";
  EXPECT_LT(live.LastUpdate().surfaceless, n) << "the voxel lies on the surface";
  EXPECT_EQ(live.LastUpdate().rewrittenTriangles, 0);
  EXPECT_NE(Area(live.GetOutput()), before) << "the vertices moved";
  ExpectSameSurface(live.GetOutput(), bone, 8);

  RemoveOwnedAt(bone, c[0], c[1], c[2], bm::Voxmap::kFull / 2); // now below the iso
  const int m = live.Update(bone);
  EXPECT_LT(live.LastUpdate().patched, m) << "the voxel's cells changed their cases";
  EXPECT_GT(live.LastUpdate().rewrittenTriangles, 0);
  ExpectSameSurface(live.GetOutput(), bone, 8);
}

TEST(BoneSurface, ACutInsideTheBoneReExtractsOnlyBricksWithoutSurface) {
  // A voxel at the ball's centre, far from any surface, loses an eighth of its fill: its bricks
  // are re-extracted (their samples changed) but have no cell across the iso, before or after.
  bm::Voxmap bone = MakeBone();
  bm::BoneSurface live(8);
  live.Update(bone);
  const int64_t triangles = live.GetOutput()->GetNumberOfCells();
  RemoveOwnedAt(bone, 24, 19, 16, bm::Voxmap::kFull / 8);
  const int n = live.Update(bone);
  EXPECT_GT(n, 0);
  EXPECT_EQ(live.LastUpdate().surfaceless, n);
  EXPECT_EQ(live.LastUpdate().extractedTriangles, 0);
  EXPECT_EQ(live.GetOutput()->GetNumberOfCells(), triangles);
  ExpectSameSurface(live.GetOutput(), bone, 8);
}
