// bmBoneSurface.h - the bone's surface from its voxmap, re-extracted only where the bone changed.
//
// The iso-surface (default fill fraction 0.5) of the voxmap's fill fractions (bmVoxmap.h), made
// with VTK's flying edges (vtkFlyingEdges3D). The grid is cut into bricks of BrickVoxels^3 cells;
// each brick's triangles are cached, and Update() re-extracts only the bricks marked dirty since
// the last update (MarkDirty with the box the tool swept), so a live view costs the size of the
// cut, not of the bone. Neighbouring bricks share their boundary plane of samples, so their
// triangles meet without gaps (points on the shared planes are duplicated, triangles are not).
// Samples outside the grid count as void, so bone touching the grid's faces is closed.
//
// Units: world mm (points are in the voxmap's world frame). Not thread-safe: the caller makes sure
// the voxmap is not written during Update() (the live view updates from a session snapshot).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <vtkSmartPointer.h>

#include "bmVoxmap.h"

class vtkPolyData;

namespace bm {

class BoneSurface {
public:
  /// brickVoxels: edge of a brick in cells (>= 2; default 32); iso: fill fraction of the surface
  /// in (0, 1) (default 0.5, where the partial-volume fill says half the voxel is bone).
  explicit BoneSurface(int brickVoxels = 32, double iso = 0.5);
  ~BoneSurface();
  BoneSurface(const BoneSurface&) = delete;
  BoneSurface& operator=(const BoneSurface&) = delete;

  /// Marks the bricks touching the world box (mm) for re-extraction at the next Update().
  void MarkDirty(const Box3& worldBoxMm);
  /// Marks every brick (the next Update() extracts the whole surface).
  void MarkAllDirty();
  /// Re-extracts the dirty bricks from `bone` (every brick on the first call or when the grid's
  /// geometry changed) and rebuilds the output. Returns the number of bricks re-extracted.
  int Update(const Voxmap& bone);

  /// The surface (triangles, point normals "Normals" from the fill gradient), world mm. The same
  /// object is reused by later updates.
  vtkPolyData* GetOutput() const;
  /// Bricks along x, y, z (of the grid padded by one void sample on each side).
  const std::array<int, 3>& BrickDims() const { return BrickDims_; }
  int64_t NumBricks() const { return int64_t(BrickDims_[0]) * BrickDims_[1] * BrickDims_[2]; }
  int BrickVoxels() const { return Brick_; }
  double Iso() const { return Iso_; }

private:
  void Reset(const Voxmap& bone);
  vtkSmartPointer<vtkPolyData> ExtractBrick(const Voxmap& bone, int bi, int bj, int bk) const;

  int Brick_;
  double Iso_;
  std::array<int, 3> Dims_{0, 0, 0}; ///< voxmap dims the cache was built for
  double Spacing_ = 0;
  std::array<double, 3> Origin_{0, 0, 0};
  std::array<int, 3> BrickDims_{0, 0, 0};
  std::vector<vtkSmartPointer<vtkPolyData>> Bricks_; ///< per brick; null = no surface there
  std::vector<uint8_t> Dirty_;
  bool AllDirty_ = true;
  vtkSmartPointer<vtkPolyData> Output_;
};

} // namespace bm
