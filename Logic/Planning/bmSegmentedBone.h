// bmSegmentedBone.h - a voxmap's bone as what landmark detection reads: the bone fraction on the
// voxmap's axis-aligned grid (world mm), its connected bones and their surface points.
//
// Bone voxels: fraction >= 0.5. Bones: 6-connected components of bone voxels, labelled 1, 2, ...
// by decreasing size. Surface points: one per pair of 6-neighbouring voxels of which one is bone
// and the other not, where the fraction linearly interpolated between the two voxel centres is
// 0.5 (the partial-volume iso-surface, sub-voxel), with the outward unit normal (minus the
// central-difference gradient of the fraction at the bone voxel) and the bone's label.
#pragma once

#include "bmVec3.h"
#include "bmVoxmap.h"

#include <cstdint>
#include <vector>

namespace bm {

struct SurfacePoint {
  Vec3 p{};      ///< world mm
  Vec3 normal{}; ///< outward unit normal
  int label = 0; ///< bone (component) label
};

class SegmentedBone {
public:
  /// Reads the voxmap's fractions (a copy; the voxmap is not kept). Throws std::runtime_error
  /// when it holds no bone voxel.
  explicit SegmentedBone(const Voxmap& voxmap);

  const std::array<int, 3>& Dims() const { return Dims_; }
  double Spacing() const { return Spacing_; }
  const Vec3& Origin() const { return Origin_; }
  /// World position (mm) of the centre of voxel (i, j, k).
  Vec3 Centre(int i, int j, int k) const {
    return {Origin_[0] + i * Spacing_, Origin_[1] + j * Spacing_, Origin_[2] + k * Spacing_};
  }
  bool Contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < Dims_[0] && j < Dims_[1] && k < Dims_[2];
  }
  int64_t Index(int i, int j, int k) const {
    return i + int64_t(Dims_[0]) * (j + int64_t(Dims_[1]) * k);
  }
  float Fraction(int64_t idx) const { return Fraction_[size_t(idx)]; }
  /// Label of a voxel (0 = not bone).
  int Label(int64_t idx) const { return Label_[size_t(idx)]; }
  /// Label at world point p (mm); 0 outside the grid or off bone.
  int LabelAt(const Vec3& p) const;
  /// Number of bones; BoneVoxels(label) = voxels of bone `label` (1 = the largest).
  int NumBones() const { return int(Sizes_.size()); }
  int64_t BoneVoxels(int label) const { return Sizes_[size_t(label - 1)]; }
  const std::vector<SurfacePoint>& Surface() const { return Surface_; }

private:
  std::array<int, 3> Dims_{};
  double Spacing_ = 1;
  Vec3 Origin_{};
  std::vector<float> Fraction_;
  std::vector<int32_t> Label_;
  std::vector<int64_t> Sizes_;
  std::vector<SurfacePoint> Surface_;
};

} // namespace bm
