// bmBoneFractionImage.h - the voxmap's fill fractions as a vtkImageData for volume rendering,
// brought up to date by copying only the bricks that changed.
//
// One float per voxel ("BoneFraction", 0 = void .. 1 = whole voxel of bone) at the voxel
// centres, in the voxmap's world frame (mm). Update() re-reads only the voxmap's bricks whose
// change generation moved since this image last looked (Voxmap::SeenBrickGeneration, marked seen
// before the brick's fills are loaded with LoadFill), so it may run while another thread cuts
// the voxmap and never misses a change: a brick cut during the copy is copied again next time.
// The first update, or one after the grid changed, copies everything.
//
// The array is rewritten in place (and marked modified) rather than reallocated: a 512^3 voxmap
// is a 512 MB image, and a cut changes a few hundred of its 8^3 bricks per refresh.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <vtkSmartPointer.h>

#include "bmVoxmap.h"

class vtkFloatArray;
class vtkImageData;

namespace bm {

class BoneFractionImage {
public:
  BoneFractionImage();
  ~BoneFractionImage();
  BoneFractionImage(const BoneFractionImage&) = delete;
  BoneFractionImage& operator=(const BoneFractionImage&) = delete;

  /// Copies the bricks of `bone` that changed since the last update (all of them the first time,
  /// after MarkAllDirty(), or when dims, spacing or origin changed). Returns the number of bricks
  /// copied.
  int64_t Update(const Voxmap& bone);
  /// The next Update() copies everything: call it when the image is to show another voxmap of the
  /// same grid (a new session), whose generations say nothing about what this image holds.
  void MarkAllDirty() { SeenGen_.clear(); }
  /// The image (dims = voxmap dims, spacing mm, origin = centre of voxel 0 in mm, point scalars
  /// "BoneFraction"). The same object and array across updates while the grid is unchanged.
  vtkImageData* GetOutput() const;

private:
  void Reset(const Voxmap& bone);
  void CopyBrick(const Voxmap& bone, int bi, int bj, int bk);

  vtkSmartPointer<vtkImageData> Image_;
  vtkSmartPointer<vtkFloatArray> Fraction_;
  std::array<int, 3> Dims_{0, 0, 0};
  double Spacing_ = 0;
  std::array<double, 3> Origin_{0, 0, 0};
  std::vector<uint32_t> SeenGen_; ///< per voxmap brick, its generation when last copied
};

} // namespace bm
