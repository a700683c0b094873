// bmOctreeVoxmap.h - the voxmap held in an octree, as Zheng et al. (2012, 2013) do: the baseline.
//
// Each node covers a power-of-two cube of voxels and is either a leaf with one fill value for its
// whole cube or has 8 children. Uniform regions (solid bone, air) stay single leaves; a query
// walks from the root down to the leaf containing the voxel (log2 of the grid size steps).
// Removal subdivides a leaf down to the voxel first. Fill units as bmVoxmap.h.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "bmVoxmap.h"

namespace bm {

class OctreeVoxmap {
public:
  struct Node {
    int32_t child = -1;     ///< index of the first of 8 children, -1 for a leaf
    Voxmap::Fill value = 0; ///< a leaf's fill, for every voxel of its cube
  };

  /// Builds from a dense voxmap (same geometry).
  explicit OctreeVoxmap(const Voxmap& v);

  int Levels() const { return Levels_; }
  size_t NodeCount() const { return Nodes_.size(); }
  size_t MemoryBytes() const { return Nodes_.capacity() * sizeof(Node); }

  /// Walks to the leaf holding voxel (i, j, k) (inside the grid). Returns the leaf's node index;
  /// level receives its level (0 = a single voxel).
  int32_t Find(int i, int j, int k, int& level) const;
  Voxmap::Fill Value(int32_t node) const { return Nodes_[size_t(node)].value; }

  /// Splits leaves until voxel (i, j, k) has its own leaf; returns it. Not thread-safe.
  int32_t Refine(int i, int j, int k);
  /// Thread-safe removal from a voxel-level leaf, as Voxmap::Remove.
  Voxmap::Fill Remove(int32_t leaf, Voxmap::Fill amount, bool& becameVoid);

  /// Writes every voxel's fill into v (same geometry).
  void CopyTo(Voxmap& v) const;

private:
  int32_t Build(const Voxmap& v, int level, int i0, int j0, int k0);
  std::array<int, 3> Dims_{};
  int Levels_ = 0;
  int32_t Root_ = 0;
  std::vector<Node> Nodes_;
};

} // namespace bm
