// bmVoxmap.h - the bone as a uniform grid of voxels (Faieghi et al. 2020, section II-A).
//
// One contiguous 1D array, index = i + nx * (j + ny * k). Each voxel holds its remaining bone
// fill as a fixed-point fraction of the voxel volume (kFull = whole voxel, <= 0 = void) and a
// material scale (1 = cortical bone, < 1 = cancellous) that scales the cutting coefficients.
// Removal lowers the fill by the volume swept into the voxel (MODEL_NOTES section 8), so material
// is conserved and steady drilling gives a steady force. Fill may go slightly negative when several
// elements cut the last of a voxel in the same frame; any value <= 0 is void.
//
// A coarse occupancy per brick (kBrick^3 voxels) is kept current as voxels go, so whole blocks of
// tool points outside the bone can be skipped.
//
// Units: world coordinates in mm; spacing in mm (isotropic); volumes in mm^3.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace bm {

/// Allocator for the voxmap's arrays: blocks of 64 MB and more are 2 MB aligned and marked for
/// transparent huge pages before they are first touched. A 1024^3 voxmap is gigabytes, and with
/// 4 KB pages nearly every element's voxel lookup also misses the TLB.
template <class T> struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U> HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(size_t n);
  void deallocate(T* p, size_t n) noexcept;
  template <class U> bool operator==(const HugePageAllocator<U>&) const { return true; }
  template <class U> bool operator!=(const HugePageAllocator<U>&) const { return false; }
};

/// Axis-aligned box in world mm.
struct Box3 {
  std::array<double, 3> lo{0, 0, 0};
  std::array<double, 3> hi{0, 0, 0};
  bool Intersects(const Box3& o) const {
    for (int a = 0; a < 3; ++a)
      if (hi[a] < o.lo[a] || o.hi[a] < lo[a])
        return false;
    return true;
  }
};

class Voxmap {
public:
  using Fill = int32_t;
  /// Fill value of a whole voxel of bone (2^24: removal resolution 6e-8 of a voxel).
  static constexpr Fill kFull = 1 << 24;
  /// Edge of a coarse-occupancy brick, in voxels.
  static constexpr int kBrick = 8;

  Voxmap() = default;
  /// Empty (all void) grid of dims voxels, isotropic spacing in mm, origin = world position (mm)
  /// of the CENTRE of voxel (0,0,0). Throws std::invalid_argument on non-positive dims/spacing.
  Voxmap(std::array<int, 3> dims, double spacingMm, std::array<double, 3> originMm);

  Voxmap(const Voxmap& o);
  Voxmap& operator=(const Voxmap& o);

  const std::array<int, 3>& Dims() const { return Dims_; }
  double Spacing() const { return Spacing_; }
  const std::array<double, 3>& Origin() const { return Origin_; }
  int64_t NumVoxels() const { return int64_t(Dims_[0]) * Dims_[1] * Dims_[2]; }
  /// Volume of one voxel, mm^3.
  double VoxelVolume() const { return Spacing_ * Spacing_ * Spacing_; }
  /// World bounds (mm) of the grid's outer faces.
  Box3 Bounds() const;

  int64_t Index(int i, int j, int k) const {
    return i + int64_t(Dims_[0]) * (j + int64_t(Dims_[1]) * k);
  }
  bool Contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < Dims_[0] && j < Dims_[1] && k < Dims_[2];
  }
  /// World (mm) -> continuous grid coordinates (voxel centres at integers).
  std::array<double, 3> WorldToGrid(const std::array<double, 3>& p) const;
  /// Grid coordinates -> world (mm).
  std::array<double, 3> GridToWorld(const std::array<double, 3>& g) const;
  /// Voxel containing world point p (mm); false when outside the grid.
  bool VoxelAt(const std::array<double, 3>& p, std::array<int, 3>& ijk) const;

  /// Fill of a voxel in [.., kFull]; <= 0 is void.
  Fill GetFill(int64_t idx) const { return Fill_[idx]; }
  /// Set a voxel's fill (clamped to kFull); keeps the brick occupancy current. Not thread-safe.
  void SetFill(int64_t idx, Fill f);
  /// Fraction of the voxel that is bone, in [0, 1].
  double Fraction(int64_t idx) const { return Fill_[idx] <= 0 ? 0.0 : double(Fill_[idx]) / kFull; }
  /// Material scale of a voxel (1 = cortical; multiplies k_c and k_f). Default 1.
  float Material(int64_t idx) const { return Material_.empty() ? 1.0f : Material_[idx]; }
  void SetMaterial(int64_t idx, float m);
  bool HasMaterial() const { return !Material_.empty(); }

  /// Thread-safe removal of `amount` fill units (> 0) from a voxel that was bone. Returns the fill
  /// actually removed (the clamped, order-independent decrement) and sets becameVoid when this call
  /// took the voxel to void. Keeps the brick occupancy current.
  Fill Remove(int64_t idx, Fill amount, bool& becameVoid);

  /// Bone volume (mm^3): sum of positive fills times the voxel volume.
  double BoneVolume() const;
  /// Number of voxels with fill > 0.
  int64_t CountBone() const;

  // Coarse occupancy: number of bone voxels in each brick.
  const std::array<int, 3>& BrickDims() const { return BrickDims_; }
  int64_t BrickIndex(int bi, int bj, int bk) const {
    return bi + int64_t(BrickDims_[0]) * (bj + int64_t(BrickDims_[1]) * bk);
  }
  int32_t BrickCount(int64_t b) const { return BrickCount_[b].load(std::memory_order_relaxed); }
  /// True when any bone voxel lies in the voxel index box [lo, hi] (inclusive, clamped to the
  /// grid).
  bool AnyBoneIn(std::array<int, 3> lo, std::array<int, 3> hi) const;
  /// Recompute the brick occupancy from the fills (after bulk writes through MutableFill()).
  void RebuildOccupancy();

  /// Raw arrays (for backends, IO and rendering). After writing through MutableFill(), call
  /// RebuildOccupancy().
  const Fill* FillData() const { return Fill_.data(); }
  Fill* MutableFill() { return Fill_.data(); }
  const float* MaterialData() const { return Material_.empty() ? nullptr : Material_.data(); }
  const std::atomic<int32_t>* BrickData() const { return BrickCount_.data(); }

  /// Exact equality of geometry, fill and material.
  bool operator==(const Voxmap& o) const;

private:
  std::array<int, 3> Dims_{0, 0, 0};
  double Spacing_ = 1.0;
  std::array<double, 3> Origin_{0, 0, 0};
  std::vector<Fill, HugePageAllocator<Fill>> Fill_;
  std::vector<float> Material_;
  std::array<int, 3> BrickDims_{0, 0, 0};
  std::vector<std::atomic<int32_t>> BrickCount_;
};

} // namespace bm
