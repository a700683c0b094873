#include "bmBoneSurfaceShell.h"

#include <algorithm>
#include <cmath>

namespace bm {

BoneSurfaceShell::BoneSurfaceShell(Voxmap& bone) : Bone_(bone) {
  const auto d = Bone_.Dims();
  const auto bd = Bone_.BrickDims();
  const int64_t n = Bone_.StorageSize(); // per voxmap index (the padding never bone)
  PointOf_.assign(size_t(n), -1);
  Known_.resize(size_t(n));
  for (int64_t v = 0; v < n; ++v)
    Known_[size_t(v)] = Bone_.GetFill(v) > 0;
  Buckets_.resize(size_t(bd[0]) * bd[1] * bd[2]);
  Stamps_.assign(Buckets_.size(), 0);
  SeenCounts_.resize(Buckets_.size());
  for (size_t b = 0; b < SeenCounts_.size(); ++b)
    SeenCounts_[b] = Bone_.BrickCount(int64_t(b));
  const int B = Voxmap::kBrick, full = B * B * B;
  auto brickFull = [&](int bi, int bj, int bk) {
    if (bi < 0 || bj < 0 || bk < 0 || bi >= bd[0] || bj >= bd[1] || bk >= bd[2])
      return false;
    for (int a = 0; a < 3; ++a) // a brick cut by the grid's end is never "full" of interior
      if ((std::array<int, 3>{bi, bj, bk}[a] + 1) * B > d[a])
        return false;
    return Bone_.BrickCount(Bone_.BrickIndex(bi, bj, bk)) == full;
  };
  for (int bk = 0; bk < bd[2]; ++bk)
    for (int bj = 0; bj < bd[1]; ++bj)
      for (int bi = 0; bi < bd[0]; ++bi) {
        if (Bone_.BrickCount(Bone_.BrickIndex(bi, bj, bk)) == 0)
          continue;
        bool interior = true; // a full brick with 26 full neighbours holds no surface voxel
        for (int dz = -1; dz <= 1 && interior; ++dz)
          for (int dy = -1; dy <= 1 && interior; ++dy)
            for (int dx = -1; dx <= 1 && interior; ++dx)
              interior = brickFull(bi + dx, bj + dy, bk + dz);
        if (interior)
          continue;
        for (int k = bk * B; k < std::min(d[2], (bk + 1) * B); ++k)
          for (int j = bj * B; j < std::min(d[1], (bj + 1) * B); ++j)
            for (int i = bi * B; i < std::min(d[0], (bi + 1) * B); ++i) {
              const int64_t idx = Bone_.Index(i, j, k);
              if (Known_[size_t(idx)] && IsSurface(i, j, k))
                AddPoint(idx, i, j, k);
            }
      }
}

bool BoneSurfaceShell::IsSurface(int i, int j, int k) const {
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy && !dz)
          continue;
        if (!Bone_.Contains(i + dx, j + dy, k + dz))
          return true;
        if (Bone_.GetFill(Bone_.Index(i + dx, j + dy, k + dz)) <= 0)
          return true;
      }
  return false;
}

namespace {
/// The 26 neighbour directions, unit, in the order Normal sums them (dz, dy, dx from -1).
const std::array<Eigen::Vector3d, 26>& NeighbourDirections() {
  static const std::array<Eigen::Vector3d, 26> dirs = [] {
    std::array<Eigen::Vector3d, 26> d;
    size_t n = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (dx || dy || dz)
            d[n++] = Eigen::Vector3d(dx, dy, dz).normalized();
    return d;
  }();
  return dirs;
}
} // namespace

Eigen::Vector3d BoneSurfaceShell::Normal(int i, int j, int k) const {
  // The same sum, in the same order, as over Eigen::Vector3d(dx, dy, dz).normalized() each time:
  // the directions are computed once (they were 30 % of a drilling session's frame).
  const auto& dirs = NeighbourDirections();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  size_t n26 = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy && !dz)
          continue;
        const double f = Bone_.Contains(i + dx, j + dy, k + dz)
                             ? Bone_.Fraction(Bone_.Index(i + dx, j + dy, k + dz))
                             : 0.0;
        g += f * dirs[n26++];
      }
  const double n = g.norm();
  return n > 1e-12 ? Eigen::Vector3d(-g / n) : Eigen::Vector3d(0, 0, 1);
}

std::array<int, 3> BoneSurfaceShell::Brick(int i, int j, int k) const {
  return {i / Voxmap::kBrick, j / Voxmap::kBrick, k / Voxmap::kBrick};
}

void BoneSurfaceShell::AddPoint(int64_t idx, int i, int j, int k) {
  int32_t slot = PointOf_[size_t(idx)];
  const bool fresh = slot < 0;
  if (fresh) {
    if (!Free_.empty()) {
      slot = Free_.back();
      Free_.pop_back();
    } else {
      slot = int32_t(Points_.size());
      Points_.emplace_back();
    }
  }
  ++Generation_;
  const auto b = Brick(i, j, k);
  const size_t brick = size_t(Bone_.BrickIndex(b[0], b[1], b[2]));
  Stamps_[brick] = Generation_;
  SurfacePoint& p = Points_[size_t(slot)];
  const auto w = Bone_.GridToWorld({double(i), double(j), double(k)});
  p.position = {w[0], w[1], w[2]};
  p.normal = Normal(i, j, k);
  p.voxel = idx;
  p.material = Bone_.Material(idx);
  if (fresh) {
    PointOf_[size_t(idx)] = slot;
    Buckets_[brick].push_back(slot);
    ++Live_;
  }
}

void BoneSurfaceShell::KillPoint(int64_t idx) {
  const int32_t slot = PointOf_[size_t(idx)];
  if (slot < 0)
    return;
  ++Generation_;
  const auto [i, j, k] = Bone_.Coords(idx);
  const auto b = Brick(i, j, k);
  const size_t brick = size_t(Bone_.BrickIndex(b[0], b[1], b[2]));
  Stamps_[brick] = Generation_;
  auto& bucket = Buckets_[brick];
  auto it = std::find(bucket.begin(), bucket.end(), slot);
  if (it != bucket.end()) {
    *it = bucket.back();
    bucket.pop_back();
  }
  Points_[size_t(slot)].voxel = -1;
  Free_.push_back(slot);
  PointOf_[size_t(idx)] = -1;
  --Live_;
}

void BoneSurfaceShell::BrickRange(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                  std::array<int, 3>& blo, std::array<int, 3>& bhi) const {
  const auto gl = Bone_.WorldToGrid({lo(0), lo(1), lo(2)});
  const auto gh = Bone_.WorldToGrid({hi(0), hi(1), hi(2)});
  const auto bd = Bone_.BrickDims();
  for (int a = 0; a < 3; ++a) {
    blo[a] = std::max(0, int(std::floor(std::min(gl[a], gh[a]) + 0.5)) / Voxmap::kBrick);
    bhi[a] = std::min(bd[a] - 1, int(std::floor(std::max(gl[a], gh[a]) + 0.5)) / Voxmap::kBrick);
    if (std::max(gl[a], gh[a]) < -0.5)
      bhi[a] = -1;
  }
}

void BoneSurfaceShell::ForEachIn(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                 const std::function<void(const SurfacePoint&)>& fn) const {
  std::array<int, 3> blo{}, bhi{};
  BrickRange(lo, hi, blo, bhi);
  for (int bk = blo[2]; bk <= bhi[2]; ++bk)
    for (int bj = blo[1]; bj <= bhi[1]; ++bj)
      for (int bi = blo[0]; bi <= bhi[0]; ++bi)
        for (int32_t s : Buckets_[size_t(Bone_.BrickIndex(bi, bj, bk))])
          fn(Points_[size_t(s)]);
}

bool BoneSurfaceShell::EmptyIn(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
  std::array<int, 3> blo{}, bhi{};
  BrickRange(lo, hi, blo, bhi);
  for (int bk = blo[2]; bk <= bhi[2]; ++bk)
    for (int bj = blo[1]; bj <= bhi[1]; ++bj)
      for (int bi = blo[0]; bi <= bhi[0]; ++bi)
        if (!Buckets_[size_t(Bone_.BrickIndex(bi, bj, bk))].empty())
          return false;
  return true;
}

void BoneSurfaceShell::Flood(std::vector<int64_t>& seeds,
                             const std::function<bool(const Eigen::Vector3d&)>* inside,
                             int64_t& removedFill, int64_t& removed) {
  std::vector<int64_t> touched;
  for (int64_t s : seeds)
    Known_[size_t(s)] = 0;
  for (size_t q = 0; q < seeds.size(); ++q) {
    const int64_t idx = seeds[q];
    KillPoint(idx);
    const auto [i, j, k] = Bone_.Coords(idx);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (!dx && !dy && !dz)
            continue;
          const int u = i + dx, v = j + dy, w = k + dz;
          if (!Bone_.Contains(u, v, w))
            continue;
          const int64_t n = Bone_.Index(u, v, w);
          if (!Known_[size_t(n)])
            continue;
          bool gone = Bone_.GetFill(n) <= 0;
          if (!gone && inside) {
            const auto c = Bone_.GridToWorld({double(u), double(v), double(w)});
            if ((*inside)(Eigen::Vector3d(c[0], c[1], c[2]))) {
              removedFill += Bone_.GetFill(n);
              Bone_.SetFill(n, 0);
              ++removed;
              gone = true;
            }
          }
          if (gone) {
            Known_[size_t(n)] = 0;
            seeds.push_back(n);
          } else if (!(Known_[size_t(n)] & kTouched)) {
            // Each neighbour once (up to 26 seeds touch it): its normal is computed once, after
            // every removal of the flood, as the last of its repeated computations was.
            Known_[size_t(n)] |= kTouched;
            touched.push_back(n);
          }
        }
  }
  for (int64_t n : touched) {
    if (!(Known_[size_t(n)] & kKnown))
      continue;
    Known_[size_t(n)] = kKnown;
    const auto [i, j, k] = Bone_.Coords(n);
    AddPoint(n, i, j, k); // new surface point, or a fresh normal for an existing one
  }
}

int64_t BoneSurfaceShell::Sync(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::vector<int64_t> seeds;
  std::array<int, 3> blo{}, bhi{};
  BrickRange(lo, hi, blo, bhi);
  for (int bk = blo[2]; bk <= bhi[2]; ++bk)
    for (int bj = blo[1]; bj <= bhi[1]; ++bj)
      for (int bi = blo[0]; bi <= bhi[0]; ++bi) {
        const int64_t b = Bone_.BrickIndex(bi, bj, bk);
        const int32_t count = Bone_.BrickCount(b);
        if (count == SeenCounts_[size_t(b)])
          continue; // no voxel of the brick went void since its bucket was last read
        SeenCounts_[size_t(b)] = count;
        // The bucket's points and their voxels' fills are scattered: fetched ahead.
        const std::vector<int32_t>& bucket = Buckets_[size_t(b)];
        const Voxmap::Fill* fills = Bone_.FillData();
        constexpr size_t kAhead = 8;
        for (size_t k = 0; k < bucket.size(); ++k) {
          if (k + 2 * kAhead < bucket.size())
            __builtin_prefetch(&Points_[size_t(bucket[k + 2 * kAhead])]);
          if (k + kAhead < bucket.size())
            __builtin_prefetch(fills + Points_[size_t(bucket[k + kAhead])].voxel);
          const int64_t v = Points_[size_t(bucket[k])].voxel;
          if (Bone_.GetFill(v) <= 0)
            seeds.push_back(v);
        }
      }
  if (seeds.empty())
    return 0;
  int64_t fill = 0, removed = 0;
  Flood(seeds, nullptr, fill, removed);
  return int64_t(seeds.size());
}

int64_t BoneSurfaceShell::Cut(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                              const std::function<bool(const Eigen::Vector3d&)>& inside,
                              int64_t& removedFill) {
  std::vector<int64_t> seeds;
  int64_t removed = 0;
  removedFill = 0;
  ForEachIn(lo, hi, [&](const SurfacePoint& p) {
    if (inside(p.position))
      seeds.push_back(p.voxel);
  });
  for (int64_t s : seeds) {
    const Voxmap::Fill f = Bone_.GetFill(s);
    if (f > 0) {
      removedFill += f;
      ++removed;
      Bone_.SetFill(s, 0);
    }
  }
  if (!seeds.empty())
    Flood(seeds, &inside, removedFill, removed);
  return removed;
}

} // namespace bm
