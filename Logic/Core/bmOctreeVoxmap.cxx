#include "bmOctreeVoxmap.h"

#include <algorithm>
#include <atomic>

namespace bm {

OctreeVoxmap::OctreeVoxmap(const Voxmap& v) : Dims_(v.Dims()) {
  const int n = std::max({Dims_[0], Dims_[1], Dims_[2]});
  while ((1 << Levels_) < n)
    ++Levels_;
  Nodes_.reserve(1024);
  Nodes_.push_back({});
  Root_ = 0;
  int32_t built = Build(v, Levels_, 0, 0, 0);
  Nodes_[0] = Nodes_[size_t(built)];
}

int32_t OctreeVoxmap::Build(const Voxmap& v, int level, int i0, int j0, int k0) {
  const int size = 1 << level;
  if (i0 >= Dims_[0] || j0 >= Dims_[1] || k0 >= Dims_[2]) {
    Nodes_.push_back({-1, 0});
    return int32_t(Nodes_.size() - 1);
  }
  if (level == 0) {
    Nodes_.push_back({-1, v.GetFill(v.Index(i0, j0, k0))});
    return int32_t(Nodes_.size() - 1);
  }
  const int half = size / 2;
  int32_t kids[8];
  for (int c = 0; c < 8; ++c)
    kids[c] = Build(v, level - 1, i0 + ((c & 1) ? half : 0), j0 + ((c & 2) ? half : 0),
                    k0 + ((c & 4) ? half : 0));
  bool uniform = true;
  for (int c = 0; c < 8 && uniform; ++c)
    uniform = Nodes_[size_t(kids[c])].child < 0 &&
              Nodes_[size_t(kids[c])].value == Nodes_[size_t(kids[0])].value;
  if (uniform) {
    // Children were appended last, as leaves: drop them and keep one leaf.
    const Voxmap::Fill value = Nodes_[size_t(kids[0])].value;
    Nodes_.resize(size_t(kids[0]));
    Nodes_.push_back({-1, value});
    return int32_t(Nodes_.size() - 1);
  }
  // Keep the 8 children consecutive: copy them to a fresh run of 8 nodes.
  const int32_t first = int32_t(Nodes_.size());
  for (int c = 0; c < 8; ++c)
    Nodes_.push_back(Nodes_[size_t(kids[c])]);
  Nodes_.push_back({first, 0});
  return int32_t(Nodes_.size() - 1);
}

int32_t OctreeVoxmap::Find(int i, int j, int k, int& level) const {
  int32_t node = Root_;
  level = Levels_;
  while (Nodes_[size_t(node)].child >= 0) {
    --level;
    const int c = ((i >> level) & 1) | (((j >> level) & 1) << 1) | (((k >> level) & 1) << 2);
    node = Nodes_[size_t(node)].child + c;
  }
  return node;
}

int32_t OctreeVoxmap::Refine(int i, int j, int k) {
  int level = 0;
  int32_t node = Find(i, j, k, level);
  while (level > 0) {
    const int32_t first = int32_t(Nodes_.size());
    const Voxmap::Fill value = Nodes_[size_t(node)].value;
    for (int c = 0; c < 8; ++c)
      Nodes_.push_back({-1, value});
    Nodes_[size_t(node)].child = first;
    --level;
    const int c = ((i >> level) & 1) | (((j >> level) & 1) << 1) | (((k >> level) & 1) << 2);
    node = first + c;
  }
  return node;
}

Voxmap::Fill OctreeVoxmap::Remove(int32_t leaf, Voxmap::Fill amount, bool& becameVoid) {
  std::atomic_ref<Voxmap::Fill> cell(Nodes_[size_t(leaf)].value);
  const Voxmap::Fill old = cell.fetch_sub(amount, std::memory_order_relaxed);
  const Voxmap::Fill after = old - amount;
  becameVoid = old > 0 && after <= 0;
  return std::max(old, 0) - std::max(after, 0);
}

void OctreeVoxmap::CopyTo(Voxmap& v) const {
  Voxmap::Fill* f = v.MutableFill();
  int level = 0;
  for (int k = 0; k < Dims_[2]; ++k)
    for (int j = 0; j < Dims_[1]; ++j)
      for (int i = 0; i < Dims_[0]; ++i)
        f[v.Index(i, j, k)] = Nodes_[size_t(Find(i, j, k, level))].value;
  v.RebuildOccupancy();
}

} // namespace bm
