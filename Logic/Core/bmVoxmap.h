// bmVoxmap.h - the bone as a uniform grid of voxels (Faieghi et al. 2020, section II-A).
//
// One contiguous 1D array, index = i + px * (j + py * k), with row and slice pitches px >= nx and
// py >= ny (Pitch()): when a row of fills is a whole number of cache lines, each row gets one
// more line and, when a slice is then a whole number of 4 KiB, each slice one more row. Without
// them a 1024-voxel row is 4 KiB and a slice 4 MiB, so the same column of neighbouring rows and
// slices falls in one set of the 8-way L1 and L2 caches and a tool's voxel lookups evict each
// other before they are read (Docs/Performance.md section 5 gives the measured effect).
// The padding voxels are void and stay so: nothing writes them. Each voxel holds its remaining bone
// fill as a fixed-point fraction of the voxel volume (kFull = whole voxel, <= 0 = void) and a
// material scale (1 = cortical bone, < 1 = cancellous) that scales the cutting coefficients.
// Removal lowers the fill by the volume swept into the voxel (Docs/Model.md section 5), so material
// is conserved and steady drilling gives a steady force. Fill may go slightly negative when several
// elements cut the last of a voxel in the same frame; any value <= 0 is void.
//
// A coarse occupancy per brick (kBrick^3 voxels) is kept current as voxels go, so whole blocks of
// tool points outside the bone can be skipped.
//
// Change generations, per brick, tell readers on other threads (a live view of the surface) which
// bricks changed since they last looked, without a lock and without the haptic thread ever
// waiting. A brick's generation is odd while it holds changes no reader has seen: Remove() and
// SetFill() mark it odd when they change a voxel's fill (an atomic load, and a read-modify-write
// only on the first change after a reader looked, so the cutting loop pays one cached load per
// change), and SeenBrickGeneration() moves it to the next even value. A reader that calls
// SeenBrickGeneration(b) before reading the brick's fills with LoadFill() and re-reads the brick
// whenever the value differs from the one it kept never misses a change: a write it did not see
// in this pass leaves the generation odd (or moves it on) for its next pass. The fills are written
// and these loads made seq_cst, which on x86-64 compiles to the same instructions as relaxed ones
// (a locked xadd for the removal, plain moves for the loads); the ordering is what makes the
// "changed after I looked" argument hold (store-buffering between the fill and the generation).
//
// Change reach, per brick, narrows what a reader redoes: 8 bits, bit o = (x | y << 1 | z << 2) set
// when a changed voxel's coordinates within its brick are, per axis, in the brick's upper
// kReachBand voxels (1) or below them (0). A surface with marching-cubes cells shifted by two
// voxels against the bricks (bm::BoneSurface) needs to redo the next brick on an axis only for
// changes in that band. Nothing is recorded until a reader asks (WantBrickReach); then the
// removal path of owned voxels (RemoveOwned, the CPU engine's) records exact bits and every other
// write all eight. A reader that finds no bits for a changed brick takes all eight.
// TakeBrickReach() hands the bits to a reader and clears them; they are exact for a reader that
// is the brick's only one (see TakeBrickReach for how a reader knows).
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
/// 4 KB pages nearly every element's voxel lookup also misses the TLB. Smaller blocks are aligned
/// to a 64-byte cache line.
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
  /// The upper band of a brick, per axis, that its change reach tells apart (voxels kBrick - 3
  /// .. kBrick - 1 of the brick; see the file comment).
  static constexpr int kReachBand = 3;
  /// All eight reach bits: any octant (what writes without exact reach record).
  static constexpr uint8_t kReachAll = 0xFF;

  Voxmap() = default;
  /// Empty (all void) grid of dims voxels, isotropic spacing in mm, origin = world position (mm)
  /// of the CENTRE of voxel (0,0,0). Throws std::invalid_argument on non-positive dims/spacing.
  Voxmap(std::array<int, 3> dims, double spacingMm, std::array<double, 3> originMm);

  Voxmap(const Voxmap& o);
  Voxmap& operator=(const Voxmap& o);
  /// Moves take the arrays (a 1024^3 voxmap is gigabytes: a setup built around a bone must not
  /// copy it); the moved-from voxmap is empty (no voxels). Not while another thread reads either.
  Voxmap(Voxmap&& o) noexcept;
  Voxmap& operator=(Voxmap&& o) noexcept;

  const std::array<int, 3>& Dims() const { return Dims_; }
  double Spacing() const { return Spacing_; }
  const std::array<double, 3>& Origin() const { return Origin_; }
  /// Voxels of the grid, nx * ny * nz (the padding not counted).
  int64_t NumVoxels() const { return int64_t(Dims_[0]) * Dims_[1] * Dims_[2]; }
  /// Entries of FillData() (and of MaterialData() when present): px * py * nz, the grid's voxels
  /// and the void padding voxels between its rows and slices.
  int64_t StorageSize() const { return int64_t(Pitch_[0]) * Pitch_[1] * Dims_[2]; }
  /// Row and slice pitch {px, py} in voxels (see the file comment): Index(i, j, k) =
  /// i + px * (j + py * k).
  const std::array<int, 2>& Pitch() const { return Pitch_; }
  /// The pitch a grid of `dims` voxels gets: px = nx + 16 when nx is a multiple of 16 (a row of
  /// whole 64-byte lines), else nx; py = ny + 1 when px * ny is a multiple of 1024 (a slice of
  /// whole 4 KiB), else ny.
  static std::array<int, 2> PitchFor(const std::array<int, 3>& dims);
  /// Volume of one voxel, mm^3.
  double VoxelVolume() const { return Spacing_ * Spacing_ * Spacing_; }
  /// World bounds (mm) of the grid's outer faces.
  Box3 Bounds() const;

  int64_t Index(int i, int j, int k) const {
    return i + int64_t(Pitch_[0]) * (j + int64_t(Pitch_[1]) * k);
  }
  /// Voxel coordinates (i, j, k) of a grid voxel's index (the inverse of Index()).
  std::array<int, 3> Coords(int64_t idx) const {
    const auto c = CoordsOfVoxel(idx);
    return {int(c[0]), int(c[1]), int(c[2])};
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

  /// Fill of a voxel in [.., kFull]; <= 0 is void. Plain read: for the thread that cuts.
  Fill GetFill(int64_t idx) const { return Fill_[idx]; }
  /// Fill of a voxel read as an atomic (seq_cst) load: safe while another thread cuts the voxmap
  /// with Remove() (a view refreshing from the live bone). Use with SeenBrickGeneration().
  Fill LoadFill(int64_t idx) const {
    return std::atomic_ref<Fill>(const_cast<Fill&>(Fill_[size_t(idx)]))
        .load(std::memory_order_seq_cst);
  }
  /// Fills of the n consecutive voxels from idx into out[0..n), each read as a relaxed atomic
  /// load (a plain move on x86-64, with the voxmap's pointer read once for the row): for a
  /// reader of a live voxmap after SeenBrickGeneration(), whose read-modify-write orders these
  /// loads after every change it does not report (see the file comment), as LoadFill() does.
  void LoadFillRow(int64_t idx, int n, Fill* out) const {
    Fill* p = const_cast<Fill*>(Fill_.data()) + idx;
    for (int x = 0; x < n; ++x)
      out[x] = std::atomic_ref<Fill>(p[x]).load(std::memory_order_relaxed);
  }
  /// Set a voxel's fill (clamped to kFull); keeps the brick occupancy current and marks the
  /// brick's generation changed when the fill changes. Not thread-safe against other writers
  /// (safe against LoadFill() readers).
  void SetFill(int64_t idx, Fill f);
  /// Fraction of the voxel that is bone, in [0, 1].
  double Fraction(int64_t idx) const { return Fill_[idx] <= 0 ? 0.0 : double(Fill_[idx]) / kFull; }
  /// Material scale of a voxel (1 = cortical; multiplies k_c and k_f). Default 1.
  float Material(int64_t idx) const { return Material_.empty() ? 1.0f : Material_[idx]; }
  void SetMaterial(int64_t idx, float m);
  bool HasMaterial() const { return !Material_.empty(); }

  /// Thread-safe removal of `amount` fill units (> 0) from a voxel that was bone. Returns the fill
  /// actually removed (the clamped, order-independent decrement) and sets becameVoid when this call
  /// took the voxel to void. Keeps the brick occupancy current and, when the voxel held bone (its
  /// fraction changed), marks the brick's generation changed.
  Fill Remove(int64_t idx, Fill amount, bool& becameVoid);

  /// Fills per 64-byte cache line (the fills are 4-byte, the array is 64-byte aligned).
  static constexpr int kFillsPerLine = 16;
  /// Owner of a voxel among `partsMask + 1` removal threads (a power of two): its cache line's
  /// index modulo the parts, so owners never share a line (no false sharing) and a thread's
  /// part is spread evenly over any region.
  static int LineOwner(int64_t idx, int partsMask) {
    return int((uint64_t(idx) / kFillsPerLine) & uint64_t(partsMask));
  }
  /// A removal request: `units` (> 0) of fill from voxel index `voxel`, whose occupancy brick
  /// (BrickOfVoxel) is `brick`.
  struct RemovalRequest {
    int64_t voxel = 0;
    int32_t units = 0;
    int32_t brick = 0;
  };
  /// Fill units and voxels that a batch of removals took.
  struct RemovalTotals {
    int64_t fill = 0;   ///< fill units removed (clamped at void, as Remove() returns them)
    int64_t voxels = 0; ///< voxels that became void
  };
  /// Removal by a thread that OWNS the requests' voxels: no other thread writes those fills
  /// during the call (as LineOwner partitions them; other owners may work on other voxels at the
  /// same time, readers may load). Same fills, totals and occupancy as Remove() on each request,
  /// in any order, a voxel any number of times; but with plain loads and stores instead of a
  /// locked decrement per request, which costs most of a removal when the fills are in cache.
  /// Appends to `touched` the bricks of voxels that held bone: pass them to MarkBricksChanged()
  /// once the owner's last batch of the frame is done.
  RemovalTotals RemoveOwned(const RemovalRequest* requests, size_t n,
                            std::vector<int64_t>& touched);
  /// Marks the bricks changed (generations odd) after a fence that orders every fill written
  /// by this thread before it (the ordering Remove() gets from its locked decrement). Entries
  /// are as RemoveOwned appends them: the brick in the low 56 bits, its reach bits (0 = unknown:
  /// all) in the top 8.
  void MarkBricksChanged(const std::vector<int64_t>& bricks);
  /// Bits of a `touched` entry below the reach bits (RemoveOwned, MarkBricksChanged).
  static constexpr int kTouchedReachShift = 56;

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
  /// Recompute the brick occupancy from the fills (after bulk writes through MutableFill()); marks
  /// every brick's generation changed (bulk writes say nothing about where they wrote).
  void RebuildOccupancy();

  // Change generations (see the file comment): one per occupancy brick, same indexing.
  /// Brick holding voxel index idx (as BrickIndex of the voxel's i/kBrick, j/kBrick, k/kBrick).
  int64_t BrickOfVoxel(int64_t idx) const;
  /// The brick's current generation (seq_cst load; odd = changed since a reader last looked).
  uint32_t BrickGeneration(int64_t b) const { return BrickGen_[size_t(b)].load(); }
  /// Marks brick b seen and returns its generation as of now, always even. Call it before
  /// reading the brick's fills (LoadFill); keep the value; the brick changed since then exactly
  /// when a later call returns a different value. Any thread, any number of readers (each keeps
  /// its own values); cost: one load, plus one compare-and-swap when the brick changed.
  uint32_t SeenBrickGeneration(int64_t b) const;

  /// Asks writers to record exact change reach from now on (the CPU engine's removal computes
  /// each changed voxel's coordinates for it: two multiplies per voxel). Any thread; stays on.
  void WantBrickReach() const { ReachWanted_.store(true, std::memory_order_relaxed); }
  /// The reach bits (see the file comment) of the changes since the last call, cleared. Call it
  /// after SeenBrickGeneration(b), and only when that returned a new value: then the bits cover
  /// every change since the reader's previous look when the generation moved by exactly 2 (no
  /// other reader looked in between) and they are not 0; otherwise use kReachAll. One
  /// exchange.
  uint8_t TakeBrickReach(int64_t b) const {
    return BrickReach_[size_t(b)].exchange(0, std::memory_order_seq_cst);
  }
  /// The reach bit of voxel idx's position in its brick (one of kReachAll's eight).
  uint8_t ReachBitOfVoxel(int64_t idx) const;

  /// Raw arrays of StorageSize() entries, voxel (i, j, k) at Index(i, j, k) (for backends, IO
  /// and rendering). Write only the grid's voxels, never the padding; after writing through
  /// MutableFill(), call RebuildOccupancy().
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
  std::array<int, 2> Pitch_{0, 0};
  std::vector<Fill, HugePageAllocator<Fill>> Fill_;
  std::vector<float> Material_;
  std::array<int, 3> BrickDims_{0, 0, 0};
  std::vector<std::atomic<int32_t>> BrickCount_;
  /// Per-brick change generations; mutable: readers holding a const Voxmap mark them seen.
  mutable std::vector<std::atomic<uint32_t>> BrickGen_;
  /// Per-brick change reach (see the file comment); mutable: readers take it.
  mutable std::vector<std::atomic<uint8_t>> BrickReach_;
  mutable std::atomic<bool> ReachWanted_{false};
  /// Reciprocals for BrickOfVoxel: ceil(2^64 / px) and ceil(2^64 / py) (exact quotients of
  /// indices below 2^52 by one multiply-high each, cheaper than division on the removal path).
  uint64_t InvNx_ = 0, InvNy_ = 0;

  void InitBricks();
  /// RemoveOwned's loop, recording reach bits (kReach) or not.
  template <bool kReach>
  RemovalTotals RemoveOwnedLoop(const RemovalRequest* requests, size_t n,
                                std::vector<int64_t>& touched);
  /// Voxel coordinates of index idx (multiply-high by the reciprocals: exact below 2^52).
  std::array<uint64_t, 3> CoordsOfVoxel(int64_t idx) const;
  /// Adds `reach` to brick b's change reach when a reader wants it (else the reach stays as it
  /// is: a reader that finds none takes all eight), then marks it changed (odd generation)
  /// unless it already is; each step a load first, a read-modify-write only when it changes
  /// something. Without a reader of reach no second array is touched: one cache miss per brick.
  void MarkBrickChanged(int64_t b, uint8_t reach = kReachAll) {
    if (ReachWanted_.load(std::memory_order_relaxed)) {
      std::atomic<uint8_t>& r = BrickReach_[size_t(b)];
      if ((r.load(std::memory_order_seq_cst) & reach) != reach)
        r.fetch_or(reach, std::memory_order_seq_cst);
    }
    std::atomic<uint32_t>& g = BrickGen_[size_t(b)];
    if (!(g.load(std::memory_order_seq_cst) & 1u))
      g.fetch_or(1u, std::memory_order_seq_cst);
  }
};

} // namespace bm
