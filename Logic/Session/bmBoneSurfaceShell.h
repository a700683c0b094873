// bmBoneSurfaceShell.h - the bone surface as a point shell with normals (Kim, Park & Park 2008
// sections 2.1 and 2.4).
//
// A surface voxel is a bone voxel (fill > 0) with at least one void 26-neighbour (outside the grid
// counts as void); each carries one point at its centre with the outward normal (the negative
// gradient of the bone fraction over the 26-neighbourhood) and its material scale. Points are
// bucketed by the voxmap's bricks so a query touches only the bricks under the tool.
//
// Regeneration after removal (Kim et al.'s flood fill): the removed voxels are the seeds; each
// seed's point is deleted, and its 26 neighbours are visited: a neighbour that is still bone
// becomes (or stays, with a fresh normal) a surface point; a neighbour that the shell knew as bone
// but is now void (removed in the same frame) is a seed too. Removal may come from the engine
// (material-conserving: Sync() finds the points whose voxel went void) or from Kim et al.'s
// Boolean cut (Cut(): voxels whose centre lies inside the tool go at once). Sync() reads only the
// buckets of the bricks whose occupancy count (Voxmap::BrickCount) changed since it last read
// them: removal only lowers fills, so a brick whose count is unchanged has no voxel that went void
// and its live points need no look (same seeds, in the same order, as reading every bucket).
//
// Change stamps, per brick, let a reader of the points (the contact's candidates,
// bmKimParkContact.h) redo only the bricks whose points changed: BrickStamp() is the Generation()
// of the last change (a point added, removed or refreshed) in that brick.
//
// One thread at a time (the haptic thread). Units: world mm.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "bmVoxmap.h"

namespace bm {

struct SurfacePoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero(); ///< voxel centre, world mm
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();   ///< outward unit normal
  int64_t voxel = -1;                                 ///< voxel index; -1 = deleted slot
  float material = 1;                                 ///< voxel material scale (stiffness scale)
};

class BoneSurfaceShell {
public:
  /// Builds the shell of the whole voxmap (the voxmap must outlive the shell).
  explicit BoneSurfaceShell(Voxmap& bone);

  const Voxmap& Bone() const { return Bone_; }
  /// Live points.
  size_t Size() const { return Live_; }
  /// Calls fn(point) for the live points in bricks overlapping the world box [lo, hi] (mm).
  void ForEachIn(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                 const std::function<void(const SurfacePoint&)>& fn) const;
  /// True when no live point lies in a brick overlapping [lo, hi].
  bool EmptyIn(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;
  /// The bricks (voxmap brick coordinates, inclusive; bhi < blo on an axis: none) overlapping the
  /// world box [lo, hi] (mm): the bricks ForEachIn visits.
  void BrickRange(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::array<int, 3>& blo,
                  std::array<int, 3>& bhi) const;
  /// Point slots of brick (bi, bj, bk), in the order ForEachIn visits them.
  const std::vector<int32_t>& Bucket(int bi, int bj, int bk) const {
    return Buckets_[size_t(Bone_.BrickIndex(bi, bj, bk))];
  }
  /// The point in a slot of a Bucket.
  const SurfacePoint& Point(int32_t slot) const { return Points_[size_t(slot)]; }
  /// Changes whenever a point is added, removed or refreshed (Sync, Cut): what was read from the
  /// shell at one generation still holds while it stays the same.
  uint64_t Generation() const { return Generation_; }
  /// The Generation() of the last change to brick (bi, bj, bk)'s points (0: none since
  /// construction): a reader that read the brick at generation g has seen its points as they are
  /// now exactly when BrickStamp() <= g.
  uint64_t BrickStamp(int bi, int bj, int bk) const {
    return Stamps_[size_t(Bone_.BrickIndex(bi, bj, bk))];
  }
  /// After the engine removed material: finds the points in [lo, hi] whose voxel is now void and
  /// regenerates the shell around them. Returns the number of voxels found void.
  int64_t Sync(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
  /// Kim et al.'s Boolean cut: every bone voxel reached from the points in [lo, hi] for which
  /// inside(voxel centre, world mm) is true is set void; the shell is regenerated. Returns the
  /// number of voxels removed; removedFill gets the fill units taken.
  int64_t Cut(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
              const std::function<bool(const Eigen::Vector3d&)>& inside, int64_t& removedFill);

private:
  bool IsSurface(int i, int j, int k) const;
  Eigen::Vector3d Normal(int i, int j, int k) const;
  void AddPoint(int64_t idx, int i, int j, int k);
  void KillPoint(int64_t idx);
  std::array<int, 3> Brick(int i, int j, int k) const;
  void Flood(std::vector<int64_t>& seeds, const std::function<bool(const Eigen::Vector3d&)>* inside,
             int64_t& removedFill, int64_t& removed);

  Voxmap& Bone_;
  std::vector<SurfacePoint> Points_;
  std::vector<int32_t> Free_;
  std::vector<int32_t> PointOf_; // per voxel: point slot or -1
  std::vector<uint8_t> Known_;   // per voxel: kKnown = the shell knows it as bone (| kTouched: a
                                 // flood has it to refresh)
  static constexpr uint8_t kKnown = 1, kTouched = 2;
  std::vector<std::vector<int32_t>> Buckets_; // per brick: point slots
  std::vector<uint64_t> Stamps_;              // per brick: Generation_ of its last change
  std::vector<int32_t> SeenCounts_;           // per brick: BrickCount when Sync last read it
  size_t Live_ = 0;
  uint64_t Generation_ = 0;
};

} // namespace bm
