#include "bmVoxmap.h"

#include "bmMemoryBudget.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>
#include <sys/mman.h>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace bm {

namespace {
constexpr size_t kHugeBytes = size_t(64) << 20;
constexpr size_t kHugePage = size_t(2) << 20;
} // namespace

template <class T> T* HugePageAllocator<T>::allocate(size_t n) {
  // Smaller blocks are aligned to a cache line (Voxmap::LineOwner's lines are the real ones).
  const size_t bytes = std::max<size_t>(n * sizeof(T), 1);
  const size_t align = bytes < kHugeBytes ? 64 : kHugePage;
  void* p = std::aligned_alloc(align, (bytes + align - 1) / align * align);
  if (!p)
    throw std::bad_alloc();
  if (align == kHugePage)
    ::madvise(p, bytes, MADV_HUGEPAGE); // advice only: ignored where huge pages are off
  return static_cast<T*>(p);
}

template <class T> void HugePageAllocator<T>::deallocate(T* p, size_t) noexcept {
  std::free(p);
}

template struct HugePageAllocator<Voxmap::Fill>;

Voxmap::Voxmap(std::array<int, 3> dims, double spacingMm, std::array<double, 3> originMm)
    : Dims_(dims), Spacing_(spacingMm), Origin_(originMm) {
  for (int a = 0; a < 3; ++a)
    if (dims[a] <= 0)
      throw std::invalid_argument("Voxmap: dimension " + std::to_string(a) + " is " +
                                  std::to_string(dims[a]) + ", must be > 0");
  if (!(spacingMm > 0) || !std::isfinite(spacingMm))
    throw std::invalid_argument("Voxmap: spacing must be a positive number of mm");
  Pitch_ = PitchFor(dims);
  // A grid the machine cannot hold is refused with a message, not killed by the kernel.
  CheckMemoryBudget(uint64_t(StorageSize()) * sizeof(Fill), 0,
                    "the voxmap (" + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) +
                        " x " + std::to_string(dims[2]) + " voxels)");
  Fill_.assign(size_t(StorageSize()), 0);
  InitBricks();
  for (auto& c : BrickCount_)
    c.store(0, std::memory_order_relaxed);
}

std::array<int, 2> Voxmap::PitchFor(const std::array<int, 3>& dims) {
  const int px = dims[0] % kFillsPerLine == 0 ? dims[0] + kFillsPerLine : dims[0];
  const int py = int64_t(px) * dims[1] % 1024 == 0 ? dims[1] + 1 : dims[1];
  return {px, py};
}

void Voxmap::InitBricks() {
  for (int a = 0; a < 3; ++a)
    BrickDims_[a] = (Dims_[a] + kBrick - 1) / kBrick;
  const size_t n = size_t(BrickDims_[0]) * BrickDims_[1] * BrickDims_[2];
  BrickCount_ = std::vector<std::atomic<int32_t>>(n);
  BrickGen_ = std::vector<std::atomic<uint32_t>>(n);
  for (auto& g : BrickGen_)
    g.store(0, std::memory_order_relaxed);
  BrickReach_ = std::vector<std::atomic<uint8_t>>(n);
  for (auto& r : BrickReach_)
    r.store(kReachAll, std::memory_order_relaxed);
  auto reciprocal = [](int d) { return d <= 1 ? uint64_t(0) : ~uint64_t(0) / uint64_t(d) + 1; };
  InvNx_ = reciprocal(Pitch_[0]);
  InvNy_ = reciprocal(Pitch_[1]);
}

Voxmap::Voxmap(const Voxmap& o) {
  *this = o;
}

Voxmap& Voxmap::operator=(const Voxmap& o) {
  if (this == &o)
    return *this;
  Dims_ = o.Dims_;
  Spacing_ = o.Spacing_;
  Origin_ = o.Origin_;
  Pitch_ = o.Pitch_;
  Fill_ = o.Fill_;
  Material_ = o.Material_;
  InitBricks();
  for (size_t b = 0; b < BrickCount_.size(); ++b) {
    BrickCount_[b].store(o.BrickCount_[b].load(std::memory_order_relaxed),
                         std::memory_order_relaxed);
    BrickGen_[b].store(o.BrickGen_[b].load(std::memory_order_relaxed), std::memory_order_relaxed);
  }
  return *this;
}

Voxmap::Voxmap(Voxmap&& o) noexcept {
  *this = std::move(o);
}

Voxmap& Voxmap::operator=(Voxmap&& o) noexcept {
  if (this == &o)
    return *this;
  Dims_ = o.Dims_;
  Spacing_ = o.Spacing_;
  Origin_ = o.Origin_;
  Pitch_ = o.Pitch_;
  Fill_ = std::move(o.Fill_);
  Material_ = std::move(o.Material_);
  BrickDims_ = o.BrickDims_;
  BrickCount_ = std::move(o.BrickCount_);
  BrickGen_ = std::move(o.BrickGen_);
  BrickReach_ = std::move(o.BrickReach_);
  ReachWanted_.store(o.ReachWanted_.load(std::memory_order_relaxed), std::memory_order_relaxed);
  InvNx_ = o.InvNx_;
  InvNy_ = o.InvNy_;
  o.Dims_ = {0, 0, 0};
  o.Pitch_ = {0, 0};
  o.BrickDims_ = {0, 0, 0};
  o.Fill_.clear();
  o.Material_.clear();
  o.BrickCount_.clear();
  o.BrickGen_.clear();
  o.BrickReach_.clear();
  return *this;
}

Box3 Voxmap::Bounds() const {
  Box3 b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = Origin_[a] - 0.5 * Spacing_;
    b.hi[a] = Origin_[a] + (Dims_[a] - 0.5) * Spacing_;
  }
  return b;
}

std::array<double, 3> Voxmap::WorldToGrid(const std::array<double, 3>& p) const {
  return {(p[0] - Origin_[0]) / Spacing_, (p[1] - Origin_[1]) / Spacing_,
          (p[2] - Origin_[2]) / Spacing_};
}

std::array<double, 3> Voxmap::GridToWorld(const std::array<double, 3>& g) const {
  return {Origin_[0] + g[0] * Spacing_, Origin_[1] + g[1] * Spacing_, Origin_[2] + g[2] * Spacing_};
}

bool Voxmap::VoxelAt(const std::array<double, 3>& p, std::array<int, 3>& ijk) const {
  auto g = WorldToGrid(p);
  for (int a = 0; a < 3; ++a) {
    double f = std::floor(g[a] + 0.5);
    if (!(f >= 0 && f < Dims_[a]))
      return false;
    ijk[a] = int(f);
  }
  return true;
}

std::array<uint64_t, 3> Voxmap::CoordsOfVoxel(int64_t idx) const {
  // idx / px and row / py by multiply-high with the rounded-up reciprocals (exact below 2^52).
  const uint64_t u = uint64_t(idx);
  const uint64_t row = InvNx_ ? uint64_t((unsigned __int128)u * InvNx_ >> 64) : u;
  const uint64_t k = InvNy_ ? uint64_t((unsigned __int128)row * InvNy_ >> 64) : row;
  return {u - row * uint64_t(Pitch_[0]), row - k * uint64_t(Pitch_[1]), k};
}

uint8_t Voxmap::ReachBitOfVoxel(int64_t idx) const {
  const auto [i, j, k] = CoordsOfVoxel(idx);
  constexpr uint64_t band = kBrick - kReachBand;
  const int o =
      int(i % kBrick >= band) | int(j % kBrick >= band) << 1 | int(k % kBrick >= band) << 2;
  return uint8_t(1u << o);
}

int64_t Voxmap::BrickOfVoxel(int64_t idx) const {
  const auto [i, j, k] = CoordsOfVoxel(idx);
  return int64_t(i / kBrick) +
         int64_t(BrickDims_[0]) *
             (int64_t(j / kBrick) + int64_t(BrickDims_[1]) * int64_t(k / kBrick));
}

uint32_t Voxmap::SeenBrickGeneration(int64_t b) const {
  std::atomic<uint32_t>& g = BrickGen_[size_t(b)];
  uint32_t v = g.load(std::memory_order_seq_cst);
  // Odd: changed since a reader last looked; move it to the next even value. A failed exchange
  // means another reader did it (writers never change an odd value): retry with what it wrote.
  while (v & 1u)
    if (g.compare_exchange_weak(v, v + 1u, std::memory_order_seq_cst))
      return v + 1u;
  return v;
}

void Voxmap::SetFill(int64_t idx, Fill f) {
  f = std::min(f, kFull);
  std::atomic_ref<Fill> cell(Fill_[size_t(idx)]);
  const Fill old = cell.load(std::memory_order_relaxed);
  const bool was = old > 0, now = f > 0;
  cell.store(f, std::memory_order_seq_cst);
  if (was != now)
    BrickCount_[size_t(BrickOfVoxel(idx))].fetch_add(now ? 1 : -1, std::memory_order_relaxed);
  if ((was || now) && old != f)
    MarkBrickChanged(BrickOfVoxel(idx));
}

void Voxmap::SetMaterial(int64_t idx, float m) {
  if (Material_.empty())
    Material_.assign(Fill_.size(), 1.0f);
  Material_[idx] = m;
}

Voxmap::Fill Voxmap::Remove(int64_t idx, Fill amount, bool& becameVoid) {
  std::atomic_ref<Fill> cell(Fill_[idx]);
  // seq_cst: the same locked xadd as relaxed on x86-64; orders the fill before the generation
  // check below for readers (see the header).
  Fill old = cell.fetch_sub(amount, std::memory_order_seq_cst);
  Fill after = old - amount;
  becameVoid = old > 0 && after <= 0;
  if (old > 0) {
    const int64_t b = BrickOfVoxel(idx);
    if (becameVoid)
      BrickCount_[size_t(b)].fetch_sub(1, std::memory_order_relaxed);
    MarkBrickChanged(b);
  }
  return std::max(old, 0) - std::max(after, 0);
}

Voxmap::RemovalTotals Voxmap::RemoveOwned(const RemovalRequest* req, size_t n,
                                          std::vector<int64_t>& touched) {
  // Two copies of the loop: without a reader of reach the loop stays as lean as before (a first
  // version that tested a flag per request and touched the reach array without a reader made
  // the engine's frame 5-10 % slower at shell 1024^3 x voxmap 1024^3).
  return ReachWanted_.load(std::memory_order_relaxed) ? RemoveOwnedLoop<true>(req, n, touched)
                                                      : RemoveOwnedLoop<false>(req, n, touched);
}

template <bool kReach>
Voxmap::RemovalTotals Voxmap::RemoveOwnedLoop(const RemovalRequest* req, size_t n,
                                              std::vector<int64_t>& touched) {
  RemovalTotals t;
  constexpr size_t kAhead = 32; // requests whose fills are prefetched ahead (runs share lines)
  for (size_t i = 0; i < std::min(n, kAhead); ++i)
    __builtin_prefetch(&Fill_[size_t(req[i].voxel)], 1);
  int64_t lastBrick = -1;
  uint64_t reach = 0; // the current run's reach bits, kept in a register
  int32_t voided = 0; // voxels of the current run that became void
  // Ends the run in lastBrick: one locked decrement of its count for the run's voided voxels
  // (the bricks' counts are shared between owners; one per voxel cost 0.1-0.2 ms in the frames
  // where a layer of voxels empties at shell 1024^3 x voxmap 1024^3), its reach into touched.
  auto endRun = [&] {
    t.voxels += voided;
    if (voided)
      BrickCount_[size_t(lastBrick)].fetch_sub(voided, std::memory_order_relaxed);
    if (kReach)
      touched.back() |= int64_t(reach << kTouchedReachShift);
  };
  for (size_t i = 0; i < n; ++i) {
    if (i + kAhead < n)
      __builtin_prefetch(&Fill_[size_t(req[i + kAhead].voxel)], 1);
    const int64_t idx = req[i].voxel;
    // Only this thread writes the fill: a relaxed load and store (plain moves on x86-64),
    // atomic because readers (the live view, a descheduled pass run) may load it meanwhile.
    std::atomic_ref<Fill> cell(Fill_[size_t(idx)]);
    const Fill old = cell.load(std::memory_order_relaxed);
    const Fill after = old - req[i].units;
    cell.store(after, std::memory_order_relaxed);
    if (old <= 0)
      continue;
    t.fill += old - std::max(after, 0);
    const int64_t b = req[i].brick;
    if (b != lastBrick) { // requests come in runs within a brick: a few entries per brick
      if (lastBrick >= 0)
        endRun();
      reach = 0;
      voided = 0;
      touched.push_back(lastBrick = b);
    }
    voided += after <= 0;
    if (kReach)
      reach |= ReachBitOfVoxel(idx);
  }
  if (lastBrick >= 0)
    endRun();
  return t;
}

void Voxmap::MarkBricksChanged(const std::vector<int64_t>& bricks) {
  // The fills were stored relaxed: the fence keeps a reader that marks a brick seen and then
  // loads its fills (SeenBrickGeneration, LoadFill) from missing them (see the file comment).
  std::atomic_thread_fence(std::memory_order_seq_cst);
  constexpr int64_t brickMask = (int64_t(1) << kTouchedReachShift) - 1;
  for (int64_t e : bricks) {
    const uint8_t r = uint8_t(uint64_t(e) >> kTouchedReachShift);
    MarkBrickChanged(e & brickMask, r ? r : kReachAll);
  }
}

double Voxmap::BoneVolume() const {
  long double s = 0;
  for (Fill f : Fill_)
    if (f > 0)
      s += f;
  return double(s / kFull) * VoxelVolume();
}

int64_t Voxmap::CountBone() const {
  int64_t n = 0;
  for (Fill f : Fill_)
    n += f > 0;
  return n;
}

bool Voxmap::AnyBoneIn(std::array<int, 3> lo, std::array<int, 3> hi) const {
  std::array<int, 3> blo, bhi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(lo[a], 0);
    hi[a] = std::min(hi[a], Dims_[a] - 1);
    if (lo[a] > hi[a])
      return false;
    blo[a] = lo[a] / kBrick;
    bhi[a] = hi[a] / kBrick;
  }
  for (int bk = blo[2]; bk <= bhi[2]; ++bk)
    for (int bj = blo[1]; bj <= bhi[1]; ++bj)
      for (int bi = blo[0]; bi <= bhi[0]; ++bi)
        if (BrickCount_[BrickIndex(bi, bj, bk)].load(std::memory_order_relaxed) > 0)
          return true;
  return false;
}

void Voxmap::RebuildOccupancy() {
  for (auto& c : BrickCount_)
    c.store(0, std::memory_order_relaxed);
  for (size_t b = 0; b < BrickGen_.size(); ++b)
    MarkBrickChanged(int64_t(b));
  // One slab of bricks (kBrick slices) at a time, counted in a plain array and stored once per
  // brick; slabs are disjoint, so large voxmaps split them over threads (a 1024^3 voxmap's
  // count took a second on one thread with a locked add per bone voxel).
  const int slabs = BrickDims_[2];
  const size_t perSlab = size_t(BrickDims_[0]) * size_t(BrickDims_[1]);
  auto count = [&](int s0, int s1) {
    std::vector<int32_t> n(perSlab);
    for (int bk = s0; bk < s1; ++bk) {
      std::fill(n.begin(), n.end(), 0);
      for (int k = bk * kBrick; k < std::min(Dims_[2], (bk + 1) * kBrick); ++k)
        for (int j = 0; j < Dims_[1]; ++j) {
          const Fill* row = Fill_.data() + Index(0, j, k);
          int32_t* out = n.data() + size_t(j / kBrick) * size_t(BrickDims_[0]);
          for (int i = 0; i < Dims_[0]; ++i)
            out[i / kBrick] += row[i] > 0;
        }
      for (size_t b = 0; b < perSlab; ++b)
        BrickCount_[size_t(bk) * perSlab + b].store(n[b], std::memory_order_relaxed);
    }
  };
  const int64_t voxels = NumVoxels();
  const int T = voxels < (int64_t(1) << 24)
                    ? 1
                    : std::clamp(int(std::thread::hardware_concurrency()), 1, std::max(1, slabs));
  std::vector<std::thread> workers;
  for (int t = 1; t < T; ++t)
    workers.emplace_back(count, slabs * t / T, slabs * (t + 1) / T);
  count(0, slabs / T);
  for (auto& w : workers)
    w.join();
}

bool Voxmap::operator==(const Voxmap& o) const {
  if (Dims_ != o.Dims_ || Spacing_ != o.Spacing_ || Origin_ != o.Origin_ || Fill_ != o.Fill_)
    return false;
  if (Material_.empty() != o.Material_.empty()) {
    const Voxmap& withM = Material_.empty() ? o : *this;
    for (float m : withM.Material_)
      if (m != 1.0f)
        return false;
    return true;
  }
  return Material_ == o.Material_;
}

} // namespace bm
