// bmBoneSurface.h - the bone's surface from its voxmap, re-extracted only where the bone changed.
//
// The iso-surface (default fill fraction 0.5) of the voxmap's fills (bmVoxmap.h), made brick by
// brick with a sparse marching cubes (bmBrickMarchingCubes.h: VTK's case table, no pipeline; a
// brick costs about the reading of its samples plus its triangles, so a thin cut costs its
// surface, not the volume around it). The grid, padded by one void sample on each side (so bone
// touching the grid's faces is closed), is cut into bricks of BrickVoxels^3 cells (default 8, the
// voxmap's occupancy brick); each brick's triangles are cached, and Update() re-extracts only the
// bricks that changed since the last update: the voxmap's per-brick change generations say which
// (a changed voxmap brick marks our bricks v and v + 1 on each axis, the cells its voxels reach
// through their values and through the gradient normals next to them; so no tool box is needed
// and nothing that changed is missed; with bricks of the voxmap's size, v + 1 on an axis only
// when a changed voxel lay in the voxmap brick's upper three layers on it, as the voxmap's change
// reach says, Voxmap::TakeBrickReach), and MarkDirty() adds bricks by hand. Bricks read a
// one-sample halo, so their triangles and normals meet those of their neighbours exactly: the
// bricks together make vtkFlyingEdges3D's surface of the whole padded grid (same triangles, points
// and normals to float rounding), with the points on shared brick faces duplicated.
//
// Live use: Update() may run while another thread cuts the voxmap (Voxmap::Remove): it reads the
// fills with atomic loads after marking the bricks seen (Voxmap::SeenBrickGeneration), so a brick
// cut during its extraction is extracted again at the next Update() (every voxel a brick reads,
// halo included, reaches the brick's cells, so its voxmap brick marks it), and the cutting thread
// never waits. A time budget (SetTimeBudgetMs) bounds one update: the bricks left over stay pending
// and go first next time, so a view keeps its frame rate and catches up within a few refreshes.
//
// The output is one vtkPolyData whose arrays are patched, not rebuilt, so an update costs the
// triangles it changed, not the whole surface: the changed bricks' old triangles are removed
// together, the places they leave below the new end filled with the triangles above it (a view's
// cut changes much the same bricks each time, appended last time, so few move), and their points'
// places freed for later bricks (the points array may hold unused points, which no triangle
// references); the new triangles are appended. A brick whose triangles came out the same (its
// cells' cases did not change: the cut only moved its vertices, as a reamer's passes do in most
// of the bricks they touch) keeps its places: only its points and normals are rewritten. Arrays
// that must grow are copied into larger ones (half again); they are written whole, in order, only
// when half their points are unused. One polydata rather than a composite of per-brick pieces: the
// BM Session source's port stays a vtkPolyData, and the mapper draws one buffer instead of
// thousands of blocks (a 512^3 voxmap holds 274625 bricks of 8).
//
// Units: world mm (points are in the voxmap's world frame); times in ms.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <vtkSmartPointer.h>

#include "bmBrickMarchingCubes.h"
#include "bmVoxmap.h"

class vtkFloatArray;
class vtkPolyData;
class vtkTypeInt32Array;

namespace bm {

class BoneSurface {
public:
  /// brickVoxels: edge of a brick in cells (2..256; default Voxmap::kBrick = 8: a changed voxmap
  /// brick then re-extracts 8 bricks of 8^3 cells, where with 32 it re-extracts 1-8 bricks of 32^3,
  /// reading up to 64 times the samples); iso: fill fraction of the surface in (0, 1) (default 0.5,
  /// where the partial-volume fill says half the voxel is bone).
  explicit BoneSurface(int brickVoxels = Voxmap::kBrick, double iso = 0.5);
  ~BoneSurface();
  BoneSurface(const BoneSurface&) = delete;
  BoneSurface& operator=(const BoneSurface&) = delete;

  /// Marks the bricks touching the world box (mm) for re-extraction at the next Update() (not
  /// needed for changes made through the Voxmap's setters, which Update() finds itself).
  void MarkDirty(const Box3& worldBoxMm);
  /// Marks every brick (the next Update() extracts the whole surface).
  void MarkAllDirty();
  /// Most time one Update() spends extracting, ms (default 0 = no limit): bricks are extracted
  /// until the time is spent (at least one), the rest stay pending for the next Update(). The
  /// first update after a reset always extracts everything.
  void SetTimeBudgetMs(double ms) { BudgetMs_ = ms; }
  double TimeBudgetMs() const { return BudgetMs_; }
  /// Re-extracts the bricks whose samples changed in `bone` since the last update (found from the
  /// voxmap's change generations), those marked dirty, and those left pending (every brick on the
  /// first call or when the grid's geometry changed), then patches the output. Returns the number
  /// of bricks re-extracted. `bone` may be cut by another thread meanwhile (see above).
  int Update(const Voxmap& bone);

  /// What the last Update() did and how long each part took (ms).
  struct UpdateStats {
    int extracted = 0;     ///< bricks re-extracted
    int patched = 0;       ///< of those, bricks whose triangles stayed: points and normals patched
    int surfaceless = 0;   ///< of those, bricks with no triangles before or after
    int pending = 0;       ///< bricks left for the next update (time budget)
    double scanMs = 0;     ///< reading the voxmap's change generations
    double extractMs = 0;  ///< reading the fills and marching cubes
    double assembleMs = 0; ///< patching the output's arrays
    int64_t rewrittenTriangles = 0; ///< triangles written into the output
    int64_t extractedTriangles = 0; ///< triangles of the re-extracted bricks
  };
  const UpdateStats& LastUpdate() const { return Stats_; }

  /// The surface (triangles, point normals "Normals" from the fill gradient), world mm. The same
  /// object, and while they need not grow the same arrays, are reused by later updates.
  vtkPolyData* GetOutput() const;
  /// Bricks along x, y, z (of the grid padded by one void sample on each side).
  const std::array<int, 3>& BrickDims() const { return BrickDims_; }
  int64_t NumBricks() const { return int64_t(BrickDims_[0]) * BrickDims_[1] * BrickDims_[2]; }
  int BrickVoxels() const { return Brick_; }
  double Iso() const { return Iso_; }

private:
  /// One brick's triangles: points and normals (x, y, z each), vertex indices into its points.
  using BrickMesh = BrickMarchingCubes::Mesh;

  void Reset(const Voxmap& bone);
  void ScanGenerations(const Voxmap& bone);
  /// Brick b's first cell on each axis (voxel coordinates, bmBrickMarchingCubes.h).
  std::array<int, 3> FirstCell(int64_t b) const;
  /// Patches the output for the re-extracted bricks: `changed` (their triangles changed) are
  /// taken out and appended again, `moved` (same triangles, so the same points in the same order)
  /// get their points and normals rewritten in their places; `full` rewrites everything.
  void Assemble(const std::vector<int64_t>& changed, const std::vector<int64_t>& moved, bool full);
  void Rebuild();
  /// New output arrays for np points and nt triangles with a quarter to spare, or with keep their
  /// current contents copied and a half to spare (the old arrays stay valid for whoever still
  /// holds them).
  void Reallocate(int64_t np, int64_t nt, bool keep);
  /// Takes the bricks' triangles out of the output (the places left filled from the end) and
  /// frees their points' places.
  void RemoveBricks(const std::vector<int64_t>& bricks);
  void AddBrick(int64_t b);
  /// Rewrites brick b's points and normals in the places its points have in the output.
  void PatchBrick(int64_t b);
  int64_t BrickId(int i, int j, int k) const {
    return i + int64_t(BrickDims_[0]) * (j + int64_t(BrickDims_[1]) * k);
  }

  int Brick_;
  double Iso_;
  double BudgetMs_ = 0;
  std::array<int, 3> Dims_{0, 0, 0}; ///< voxmap dims the cache was built for
  double Spacing_ = 0;
  std::array<double, 3> Origin_{0, 0, 0};
  std::array<int, 3> BrickDims_{0, 0, 0};
  std::vector<BrickMesh> Bricks_;
  std::vector<uint8_t> Dirty_;
  int64_t Cursor_ = 0; ///< where the next budgeted update starts looking for dirty bricks
  /// An update's dirty bricks in the order it takes them; cut down to those it extracted whose
  /// triangles changed. MovedList_: those whose triangles stayed (only their points moved).
  std::vector<int64_t> DirtyList_, MovedList_;
  BrickMesh Extracted_; ///< a brick's new mesh, compared with its last before it takes its place
  bool AllDirty_ = true;
  /// Last generation seen of each of the voxmap's bricks, and for each axis the range of our
  /// bricks that a voxmap brick's samples fall into.
  std::vector<uint32_t> SeenGen_;
  /// Whether the voxmap's change reach (Voxmap::TakeBrickReach) narrows a changed voxmap brick
  /// to fewer than its eight bricks of ours (bricks of the voxmap's size only).
  bool ExactReach() const { return Brick_ == Voxmap::kBrick; }
  std::array<std::vector<std::array<int, 2>>, 3> VoxBrickRange_;

  /// Output layout: each brick's point and triangle places in the output arrays; for each
  /// triangle place, its brick and its index in that brick's list; unused point places.
  std::vector<std::vector<int32_t>> PointSlots_, TriangleSlots_;
  std::vector<int32_t> TriangleOwner_, TriangleIndex_, FreePoints_;
  int64_t NumPoints_ = 0, NumTriangles_ = 0; ///< points (unused ones included), triangles
  int64_t PointCapacity_ = 0, TriangleCapacity_ = 0, OffsetsWritten_ = 0;
  vtkSmartPointer<vtkFloatArray> Points_, Normals_;
  vtkSmartPointer<vtkTypeInt32Array> Offsets_, Connectivity_;
  vtkSmartPointer<vtkPolyData> Output_;

  BrickMarchingCubes Cubes_; ///< extracts every brick (its scratch buffers reused)

  UpdateStats Stats_;
};

} // namespace bm
