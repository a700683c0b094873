// bmBoneSurface.cxx - see bmBoneSurface.h.
#include "bmBoneSurface.h"

#include <algorithm>
#include <functional>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkTypeInt32Array.h>

namespace bm {

// The padded lattice, in voxel coordinates (bmBrickMarchingCubes.h): samples -1 .. Dims (the two
// ends void), cells -1 .. Dims - 1, cell c spanning the samples c and c + 1. Brick b holds the
// cells [b B - 2, (b + 1) B - 2): shifted by two so that the cells a voxmap brick's voxels reach
// fall into two of our bricks per axis when B = Voxmap::kBrick (see Reset).

namespace {
using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

/// A VTK array of `capacity` values, owned by VTK (freed with free()), holding `size` of them.
template <class ArrayT>
vtkSmartPointer<ArrayT> MakeArray(int components, int64_t capacity, const char* name) {
  using T = typename ArrayT::ValueType;
  auto a = vtkSmartPointer<ArrayT>::New();
  a->SetNumberOfComponents(components);
  if (name)
    a->SetName(name);
  void* p = std::malloc(size_t(std::max<int64_t>(capacity, 1)) * sizeof(T));
  if (!p)
    throw std::bad_alloc();
  a->SetArray(static_cast<T*>(p), 0, 0, ArrayT::VTK_DATA_ARRAY_FREE);
  return a;
}

/// Sets how many values of its buffer an array from MakeArray holds (no reallocation).
template <class ArrayT> void SetLength(ArrayT* a, int64_t values) {
  a->SetArray(a->GetPointer(0), vtkIdType(values), 0, ArrayT::VTK_DATA_ARRAY_FREE);
  a->Modified();
}
} // namespace

BoneSurface::BoneSurface(int brickVoxels, double iso)
    : Brick_(brickVoxels), Iso_(iso), Output_(vtkSmartPointer<vtkPolyData>::New()),
      Cubes_(brickVoxels, iso) {}

BoneSurface::~BoneSurface() = default;

vtkPolyData* BoneSurface::GetOutput() const {
  return Output_;
}

void BoneSurface::MarkAllDirty() {
  AllDirty_ = true;
}

void BoneSurface::MarkDirty(const Box3& box) {
  if (AllDirty_ || Spacing_ <= 0)
    return; // everything is extracted next time anyway
  for (int a = 0; a < 3; ++a)
    if (box.hi[a] < box.lo[a])
      return;
  std::array<int, 3> lo, hi;
  for (int a = 0; a < 3; ++a) {
    // The voxels the box touches, widened by one; a voxel i reaches the cells i - 2 .. i + 1
    // (i - 1 and i through its value, the other two through the gradients at its neighbours).
    const double glo = (box.lo[a] - Origin_[a]) / Spacing_,
                 ghi = (box.hi[a] - Origin_[a]) / Spacing_;
    const double end = double(Dims_[a]);
    const int ilo = int(std::floor(std::clamp(glo, -1.0, end))) - 1;
    const int ihi = int(std::ceil(std::clamp(ghi, -1.0, end))) + 1;
    lo[a] = std::clamp((ilo - 2 + 2) / Brick_, 0, BrickDims_[a] - 1);
    hi[a] = std::clamp((ihi + 1 + 2) / Brick_, 0, BrickDims_[a] - 1);
  }
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i)
        Dirty_[size_t(BrickId(i, j, k))] = 1;
}

void BoneSurface::Reset(const Voxmap& bone) {
  Dims_ = bone.Dims();
  Spacing_ = bone.Spacing();
  Origin_ = bone.Origin();
  for (int a = 0; a < 3; ++a)
    BrickDims_[a] = (Dims_[a] + 1) / Brick_ + 1; // the last holds cell Dims - 1
  if (NumBricks() > INT32_MAX)
    throw std::length_error("BoneSurface: more than 2^31 bricks");
  const size_t n = size_t(NumBricks());
  Bricks_.assign(n, BrickMesh{});
  Dirty_.assign(n, 1);
  PointSlots_.assign(n, {});
  TriangleSlots_.assign(n, {});
  Cursor_ = 0;
  AllDirty_ = false;
  // Our bricks that each of the voxmap's bricks reaches, per axis: voxmap brick v holds the voxels
  // i0..i1 below; voxel i reaches the cells i - 2 .. i + 1 (the cells around it through its value,
  // one further through the central-difference normals of the vertices next to it), and cell c
  // lies in our brick (c + 2) / B. With B = kBrick that is our bricks v and v + 1.
  const auto& vbd = bone.BrickDims();
  for (int a = 0; a < 3; ++a) {
    VoxBrickRange_[a].resize(size_t(vbd[a]));
    for (int v = 0; v < vbd[a]; ++v) {
      const int i0 = v * Voxmap::kBrick;
      const int i1 = std::min(i0 + Voxmap::kBrick, Dims_[a]) - 1;
      VoxBrickRange_[a][size_t(v)] = {i0 / Brick_, std::min((i1 + 3) / Brick_, BrickDims_[a] - 1)};
    }
  }
  // Everything is extracted now: mark every voxmap brick seen first (and its reach taken).
  // With bricks of the voxmap's size, a voxel reaches our brick v + 1 on an axis only from the
  // voxmap brick's upper kReachBand voxels (i - 2 .. i + 1 in our brick (c + 2) / B is v + 1
  // exactly when i % B >= B - 3): the voxmap records where changes were (ScanGenerations).
  static_assert(Voxmap::kReachBand == 3, "the band is the voxels that reach cell c + 2 and on");
  if (ExactReach())
    bone.WantBrickReach();
  SeenGen_.resize(size_t(vbd[0]) * vbd[1] * vbd[2]);
  for (size_t b = 0; b < SeenGen_.size(); ++b) {
    SeenGen_[b] = bone.SeenBrickGeneration(int64_t(b));
    bone.TakeBrickReach(int64_t(b));
  }
}

void BoneSurface::ScanGenerations(const Voxmap& bone) {
  const auto& vbd = bone.BrickDims();
  int64_t b = 0;
  for (int vk = 0; vk < vbd[2]; ++vk)
    for (int vj = 0; vj < vbd[1]; ++vj)
      for (int vi = 0; vi < vbd[0]; ++vi, ++b) {
        const uint32_t g = bone.SeenBrickGeneration(b);
        if (g == SeenGen_[size_t(b)])
          continue;
        // The reach bits cover every change since we last looked when no other reader looked
        // in between: the generation moved by exactly 2 (Voxmap::TakeBrickReach).
        uint8_t reach = bone.TakeBrickReach(b);
        if (reach == 0 || g - SeenGen_[size_t(b)] != 2u)
          reach = Voxmap::kReachAll;
        SeenGen_[size_t(b)] = g;
        const auto& rx = VoxBrickRange_[0][size_t(vi)];
        const auto& ry = VoxBrickRange_[1][size_t(vj)];
        const auto& rz = VoxBrickRange_[2][size_t(vk)];
        if (!ExactReach()) { // other brick sizes: every brick of ours the voxmap brick reaches
          for (int k = rz[0]; k <= rz[1]; ++k)
            for (int j = ry[0]; j <= ry[1]; ++j)
              for (int i = rx[0]; i <= rx[1]; ++i)
                Dirty_[size_t(BrickId(i, j, k))] = 1;
          continue;
        }
        // Our brick v + d (d's bits: one step up on x, y, z) is reached by a changed octant o
        // that lies in the band on every axis d steps up on, (o & d) == d; v + 1 past the grid's
        // end is where VoxBrickRange_ stops.
        for (int d = 0; d < 8; ++d) {
          bool reached = false;
          for (int o = 0; o < 8; ++o)
            reached |= (reach >> o & 1) && (o & d) == d;
          const int i = rx[0] + (d & 1), j = ry[0] + (d >> 1 & 1), k = rz[0] + (d >> 2);
          if (reached && i <= rx[1] && j <= ry[1] && k <= rz[1])
            Dirty_[size_t(BrickId(i, j, k))] = 1;
        }
      }
}

std::array<int, 3> BoneSurface::FirstCell(int64_t b) const {
  // 32-bit divisions (Reset keeps the brick count below 2^31): this runs twice per brick.
  const uint32_t i = uint32_t(b), nx = uint32_t(BrickDims_[0]), ny = uint32_t(BrickDims_[1]);
  const uint32_t row = i / nx;
  return {int(i - row * nx) * Brick_ - 2, int(row % ny) * Brick_ - 2, int(row / ny) * Brick_ - 2};
}

void BoneSurface::RemoveBricks(const std::vector<int64_t>& changed) {
  // Free the bricks' points; mark their triangles' places empty.
  int64_t removed = 0;
  for (int64_t b : changed) {
    std::vector<int32_t>& points = PointSlots_[size_t(b)];
    FreePoints_.insert(FreePoints_.end(), points.begin(), points.end());
    points.clear();
    for (int32_t slot : TriangleSlots_[size_t(b)])
      TriangleOwner_[size_t(slot)] = -1;
    removed += int64_t(TriangleSlots_[size_t(b)].size());
  }
  // Fill the empty places below the new end with the triangles still above it. A view's cut
  // changes much the same bricks from one update to the next, and those were appended last, so
  // the triangles above the new end are mostly the removed ones: few moves.
  const int64_t end = NumTriangles_ - removed;
  int32_t* conn = Connectivity_->GetPointer(0);
  int64_t from = end;
  for (int64_t b : changed) {
    std::vector<int32_t>& tris = TriangleSlots_[size_t(b)];
    for (int32_t slot : tris) {
      if (slot >= end)
        continue;
      while (TriangleOwner_[size_t(from)] < 0)
        ++from;
      std::memcpy(conn + 3 * int64_t(slot), conn + 3 * from, 3 * sizeof(int32_t));
      const int32_t owner = TriangleOwner_[size_t(from)], index = TriangleIndex_[size_t(from)];
      TriangleOwner_[size_t(slot)] = owner;
      TriangleIndex_[size_t(slot)] = index;
      TriangleSlots_[size_t(owner)][size_t(index)] = slot;
      ++from;
      ++Stats_.rewrittenTriangles;
    }
    tris.clear();
  }
  NumTriangles_ = end;
}

void BoneSurface::AddBrick(int64_t b) {
  const BrickMesh& m = Bricks_[size_t(b)];
  float* pts = Points_->GetPointer(0);
  float* nrm = Normals_->GetPointer(0);
  int32_t* conn = Connectivity_->GetPointer(0);
  std::vector<int32_t>& points = PointSlots_[size_t(b)];
  points.resize(size_t(m.NumPoints()));
  for (size_t i = 0; i < points.size(); ++i) {
    int32_t slot;
    if (!FreePoints_.empty()) {
      slot = FreePoints_.back();
      FreePoints_.pop_back();
    } else {
      slot = int32_t(NumPoints_++);
    }
    points[i] = slot;
    std::memcpy(pts + 3 * int64_t(slot), m.points.data() + 3 * i, 3 * sizeof(float));
    std::memcpy(nrm + 3 * int64_t(slot), m.normals.data() + 3 * i, 3 * sizeof(float));
  }
  std::vector<int32_t>& tris = TriangleSlots_[size_t(b)];
  tris.resize(size_t(m.NumTriangles()));
  for (size_t t = 0; t < tris.size(); ++t) {
    const int32_t slot = int32_t(NumTriangles_++);
    tris[t] = slot;
    int32_t* c = conn + 3 * int64_t(slot);
    for (size_t q = 0; q < 3; ++q)
      c[q] = points[size_t(m.triangles[3 * t + q])];
    TriangleOwner_[size_t(slot)] = int32_t(b);
    TriangleIndex_[size_t(slot)] = int32_t(t);
  }
  Stats_.rewrittenTriangles += int64_t(tris.size());
}

void BoneSurface::PatchBrick(int64_t b) {
  const BrickMesh& m = Bricks_[size_t(b)];
  float* pts = Points_->GetPointer(0);
  float* nrm = Normals_->GetPointer(0);
  const std::vector<int32_t>& points = PointSlots_[size_t(b)];
  for (size_t i = 0; i < points.size(); ++i) {
    std::memcpy(pts + 3 * int64_t(points[i]), m.points.data() + 3 * i, 3 * sizeof(float));
    std::memcpy(nrm + 3 * int64_t(points[i]), m.normals.data() + 3 * i, 3 * sizeof(float));
  }
}

void BoneSurface::Rebuild() {
  // Sizes of the result, and whether the current arrays hold it.
  int64_t np = 0, nt = 0;
  for (const BrickMesh& m : Bricks_) {
    np += m.NumPoints();
    nt += m.NumTriangles();
  }
  if (!Points_ || np > PointCapacity_ || nt > TriangleCapacity_)
    Reallocate(np, nt, false);
  // Rewrite the arrays in place, in order.
  FreePoints_.clear();
  NumPoints_ = NumTriangles_ = 0;
  for (size_t b = 0; b < Bricks_.size(); ++b) {
    PointSlots_[b].clear();
    TriangleSlots_[b].clear();
    AddBrick(int64_t(b));
  }
}

void BoneSurface::Reallocate(int64_t np, int64_t nt, bool keep) {
  // New arrays with room to grow; the old ones stay valid for whoever still holds them.
  const vtkSmartPointer<vtkFloatArray> oldPoints = Points_, oldNormals = Normals_;
  const vtkSmartPointer<vtkTypeInt32Array> oldConnectivity = Connectivity_;
  keep = keep && Points_;
  const int64_t spare = keep ? 2 : 4; // growing while cutting: a half to spare, else a quarter
  PointCapacity_ = std::max<int64_t>(np + np / spare, 1024);
  TriangleCapacity_ = std::max<int64_t>(nt + nt / spare, 1024);
  if (PointCapacity_ > INT32_MAX || 3 * TriangleCapacity_ > INT32_MAX)
    throw std::length_error("BoneSurface: surface too large for 32-bit connectivity");
  Points_ = MakeArray<vtkFloatArray>(3, 3 * PointCapacity_, nullptr);
  Normals_ = MakeArray<vtkFloatArray>(3, 3 * PointCapacity_, "Normals");
  Offsets_ = MakeArray<vtkTypeInt32Array>(1, TriangleCapacity_ + 1, nullptr);
  Connectivity_ = MakeArray<vtkTypeInt32Array>(1, 3 * TriangleCapacity_, nullptr);
  if (keep) {
    // Everything stays where it was: copy the arrays, the slot lists stay right.
    std::memcpy(Points_->GetPointer(0), oldPoints->GetPointer(0),
                size_t(3 * NumPoints_) * sizeof(float));
    std::memcpy(Normals_->GetPointer(0), oldNormals->GetPointer(0),
                size_t(3 * NumPoints_) * sizeof(float));
    std::memcpy(Connectivity_->GetPointer(0), oldConnectivity->GetPointer(0),
                size_t(3 * NumTriangles_) * sizeof(int32_t));
    TriangleOwner_.resize(size_t(TriangleCapacity_), 0);
    TriangleIndex_.resize(size_t(TriangleCapacity_), 0);
  } else {
    TriangleOwner_.assign(size_t(TriangleCapacity_), 0);
    TriangleIndex_.assign(size_t(TriangleCapacity_), 0);
  }
  OffsetsWritten_ = 0;
  Offsets_->GetPointer(0)[0] = 0;
  vtkNew<vtkPoints> points;
  points->SetData(Points_);
  Output_->SetPoints(points);
  Output_->GetPointData()->SetNormals(Normals_);
  vtkNew<vtkCellArray> polys;
  polys->SetData(Offsets_, Connectivity_);
  Output_->SetPolys(polys);
}

void BoneSurface::Assemble(const std::vector<int64_t>& changed, const std::vector<int64_t>& moved,
                           bool full) {
  // Patch in place when no more than half of the points would be unused (in larger arrays, the
  // contents copied, when these do not hold the result: a cut that grows the surface costs a copy,
  // not a rewrite from every brick); otherwise write everything again.
  int64_t oldPoints = 0, newPoints = 0, oldTriangles = 0, newTriangles = 0;
  for (int64_t b : changed) {
    oldPoints += int64_t(PointSlots_[size_t(b)].size());
    oldTriangles += int64_t(TriangleSlots_[size_t(b)].size());
    newPoints += Bricks_[size_t(b)].NumPoints();
    newTriangles += Bricks_[size_t(b)].NumTriangles();
  }
  const int64_t unused = int64_t(FreePoints_.size()) + oldPoints;
  const int64_t points = NumPoints_ + std::max<int64_t>(0, newPoints - unused);
  const int64_t triangles = NumTriangles_ - oldTriangles + newTriangles;
  const int64_t unusedAfter = std::max<int64_t>(0, unused - newPoints);
  if (full || !Points_ || (unusedAfter > 4096 && 2 * unusedAfter > points)) {
    Rebuild();
  } else {
    if (points > PointCapacity_ || triangles > TriangleCapacity_)
      Reallocate(std::max(points, NumPoints_), std::max(triangles, NumTriangles_), true);
    RemoveBricks(changed);
    for (int64_t b : changed)
      AddBrick(b);
    for (int64_t b : moved)
      PatchBrick(b);
  }
  // Every cell is a triangle: offsets are 0, 3, 6, ...; write the ones not yet written.
  int32_t* off = Offsets_->GetPointer(0);
  for (int64_t t = OffsetsWritten_ + 1; t <= NumTriangles_; ++t)
    off[t] = int32_t(3 * t);
  OffsetsWritten_ = std::max(OffsetsWritten_, NumTriangles_);
  SetLength(Points_.Get(), 3 * NumPoints_);
  SetLength(Normals_.Get(), 3 * NumPoints_);
  SetLength(Offsets_.Get(), NumTriangles_ + 1);
  SetLength(Connectivity_.Get(), 3 * NumTriangles_);
  Output_->GetPoints()->Modified();
  Output_->GetPolys()->Modified();
  Output_->Modified();
}

int BoneSurface::Update(const Voxmap& bone) {
  Stats_ = UpdateStats{};
  const auto t0 = Clock::now();
  const bool full =
      AllDirty_ || bone.Dims() != Dims_ || bone.Spacing() != Spacing_ || bone.Origin() != Origin_;
  if (full)
    Reset(bone);
  else
    ScanGenerations(bone);
  const auto t1 = Clock::now();

  // The dirty bricks, from where the last budgeted update stopped; each one's first slices of
  // fills are asked of the memory one brick ahead (BrickMarchingCubes::Prefetch: the voxmap's rows
  // are cache misses, most of a brick's cost else).
  DirtyList_.clear();
  MovedList_.clear();
  const int64_t n = NumBricks();
  const int64_t start = full ? 0 : Cursor_;
  for (int64_t i = 0, b = start; i < n; ++i, b = b + 1 == n ? 0 : b + 1)
    if (Dirty_[size_t(b)])
      DirtyList_.push_back(b);
  const bool budget = BudgetMs_ > 0 && !full;
  size_t done = 0;
  for (; done < DirtyList_.size(); ++done) {
    if (budget && done > 0 && Ms(t1, Clock::now()) >= BudgetMs_)
      break;
    if (done + 1 < DirtyList_.size())
      Cubes_.Prefetch(bone, FirstCell(DirtyList_[done + 1]));
    const int64_t b = DirtyList_[done];
    BrickMesh& mesh = Bricks_[size_t(b)];
    Cubes_.Extract(bone, FirstCell(b), Extracted_);
    // The same triangles (vertex indices) make the same points in the same order: the cases of
    // the brick's cells, which alone decide both, did not change. (The output holds the brick's
    // last mesh: every extracted brick is assembled in the same update.)
    if (!full && Extracted_.triangles == mesh.triangles &&
        Extracted_.NumPoints() == mesh.NumPoints()) {
      MovedList_.push_back(b);
      Stats_.surfaceless += Extracted_.triangles.empty();
    }
    std::swap(mesh, Extracted_);
    Stats_.extractedTriangles += mesh.NumTriangles();
    Dirty_[size_t(b)] = 0;
  }
  Cursor_ = done < DirtyList_.size() ? DirtyList_[done] : start;
  Stats_.extracted = int(done);
  Stats_.pending = int(DirtyList_.size() - done);
  Stats_.patched = int(MovedList_.size());
  // Now the bricks this update extracted whose triangles changed (both lists in the same order).
  DirtyList_.resize(done);
  size_t kept = 0;
  for (size_t i = 0, m = 0; i < DirtyList_.size(); ++i) {
    if (m < MovedList_.size() && DirtyList_[i] == MovedList_[m])
      ++m;
    else
      DirtyList_[kept++] = DirtyList_[i];
  }
  DirtyList_.resize(kept);
  const auto t2 = Clock::now();
  if (!DirtyList_.empty() || !MovedList_.empty() || !Points_)
    Assemble(DirtyList_, MovedList_, full);
  const auto t3 = Clock::now();

  Stats_.scanMs = Ms(t0, t1);
  Stats_.extractMs = Ms(t1, t2);
  Stats_.assembleMs = Ms(t2, t3);
  return Stats_.extracted;
}

} // namespace bm
