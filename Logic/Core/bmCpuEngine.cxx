#include "bmCpuEngine.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "bmFrameGeometry.h"
#include "bmIncrementalPass.h"
#include "bmMorton.h"

namespace bm {

void RequestList::Reserve(size_t n) {
  if (Storage_ && Size_ + n <= Capacity_)
    return;
  const size_t cap = std::max(Size_ + n, Capacity_ + Capacity_ / 2);
  std::unique_ptr<Voxmap::RemovalRequest[]> storage(new Voxmap::RemovalRequest[cap + 1]);
  storage[0].voxel = kNoVoxel;
  if (Storage_)
    std::copy(Data(), Data() + Size_, storage.get() + 1);
  Storage_ = std::move(storage);
  Capacity_ = cap;
}

void FramePartial::Clear() {
  thrust = torque = fx = fy = 0;
  visited = engaged = engagedCutting = requested = 0;
  removedFill = removedVoxels = 0;
  for (auto& r : removals)
    r.Clear();
}

void FramePartial::SetSums(int64_t thrustSum, int64_t torqueSum, int64_t fxSum, int64_t fySum,
                           int64_t visitedCount, int64_t engagedCount, int64_t engagedCuttingCount,
                           int64_t requestedUnits) {
  thrust = thrustSum;
  torque = torqueSum;
  fx = fxSum;
  fy = fySum;
  visited = visitedCount;
  engaged = engagedCount;
  engagedCutting = engagedCuttingCount;
  requested = requestedUnits;
}

void FramePartial::Add(const FramePartial& o) {
  thrust += o.thrust;
  torque += o.torque;
  fx += o.fx;
  fy += o.fy;
  visited += o.visited;
  engaged += o.engaged;
  engagedCutting += o.engagedCutting;
  requested += o.requested;
  removedFill += o.removedFill;
  removedVoxels += o.removedVoxels;
}

namespace {

// Memory a worker may still read while it finishes a task it has lost (bmWorkerPool.h
// RunRedoable: its results are thrown away) and the caller rewrites in a later frame: the fills
// (removal), the residency buffers and the force table. Accessed as relaxed atomics, which on
// x86-64 are the same plain moves, so that access is no data race.
template <class T> T LoadRelaxed(const T& v) {
  return std::atomic_ref<T>(const_cast<T&>(v)).load(std::memory_order_relaxed);
}
template <class T> void StoreRelaxed(T& v, T x) {
  std::atomic_ref<T>(v).store(x, std::memory_order_relaxed);
}

} // namespace

bool BlockVisible(const ShellBlock& blk, const FrameGeometry& G, const Voxmap& bone,
                  const CullingOptions& culling) {
  if (culling.motion && !blk.hasCutting) {
    double up = 0;
    for (int a = 0; a < 3; ++a)
      up += std::max(blk.nLo[a] * G.motionTool(a), blk.nHi[a] * G.motionTool(a));
    if (up <= 0 || !G.remove)
      return false;
  }
  if (!culling.blocks)
    return true;
  std::array<int, 3> lo, hi;
  G.VoxelBox(blk.lo, blk.hi, lo, hi);
  return bone.AnyBoneIn(lo, hi);
}

double MaxRemovalUnits(const Eigen::Vector3d& d, double voxelMm, double unitsPerMm3) {
  // Projected area of a voxel along d times |d|: h^2 (|dx| + |dy| + |dz|).
  const double swept = voxelMm * voxelMm * (std::abs(d(0)) + std::abs(d(1)) + std::abs(d(2)));
  return std::min(swept * unitsPerMm3, double(Voxmap::kFull));
}

FrameResult FrameResultOf(const FramePartial& p, double voxelVolume) {
  FrameResult r;
  r.thrustFixed = p.thrust;
  r.torqueFixed = p.torque;
  r.visitedElements = p.visited;
  r.engagedElements = p.engaged;
  r.engagedCutting = p.engagedCutting;
  r.removedFill = p.removedFill;
  r.removedVoxels = p.removedVoxels;
  r.thrustN = double(r.thrustFixed) / kForceFixedScale;
  r.torqueNmm = double(r.torqueFixed) / kForceFixedScale;
  r.forceTool = {double(p.fx) / kForceFixedScale, double(p.fy) / kForceFixedScale, r.thrustN};
  r.removedVolumeMm3 = double(r.removedFill) / Voxmap::kFull * voxelVolume;
  r.sweptVolumeMm3 = double(p.requested) / Voxmap::kFull * voxelVolume;
  return r;
}

CpuEngine::CpuEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell,
                     const ForceModel& model, int threads, CullingOptions culling)
    : Bone_(bone), Tool_(tool), Shell_(shell), Model_(model), Culling_(culling),
      Pool_(ValidThreads(threads)), Partials_(NumTasks(shell) * size_t(Pool_.Threads())),
      State_(Pool_.Threads() == 1 ? 1 : 2 * size_t(Pool_.Threads()),
             ResidencyBuffer{std::vector<uint64_t>(shell.Size(), 0),
                             std::vector<uint32_t>(shell.Blocks().size(), 0)}),
      PrevWinner_(NumTasks(shell), 0) {
  SmallCodes_ = std::all_of(shell.Codes().begin(), shell.Codes().end(), ElementCodeIsSmall);
  while (RemovalParts_ < Pool_.Threads())
    RemovalParts_ *= 2;
  for (FramePartial& p : Partials_)
    p.removals.resize(size_t(RemovalParts_));
  RemovalCounts_.resize(size_t(RemovalParts_));
  Touched_.resize(size_t(RemovalParts_));
  Pool_.ReserveRedoable(int(NumTasks(shell)));
  if (Pool_.Threads() == 1 && Culling_.incremental)
    Incremental_ = std::make_unique<IncrementalPass>(shell);
}

int64_t CpuEngine::IncrementalFrames() const {
  return Incremental_ ? Incremental_->FramesRun() : 0;
}

int64_t CpuEngine::IncrementalRecomputed() const {
  return Incremental_ ? Incremental_->Recomputed() : 0;
}

void CpuEngine::ForgetIncremental() {
  if (Incremental_)
    Incremental_->Forget();
}

void CpuEngine::SetIncremental(bool on) {
  Culling_.incremental = on;
  if (!on)
    Incremental_.reset();
  else if (!Incremental_ && Pool_.Threads() == 1)
    Incremental_ = std::make_unique<IncrementalPass>(Shell_); // starts with a full pass
}

int CpuEngine::ValidThreads(int threads) {
  if (threads > kMaxThreads)
    throw std::invalid_argument("CpuEngine: " + std::to_string(threads) + " threads, at most " +
                                std::to_string(kMaxThreads));
  return threads; // WorkerPool refuses fewer than 1
}

size_t CpuEngine::NumTasks(const PointShell& shell) {
  return (shell.Blocks().size() + kBlocksPerTask - 1) / kBlocksPerTask;
}

void CpuEngine::UpdateForceTable(double f, double n) {
  if (f == TableFeed_ && n == TableSpeed_)
    return;
  // In place once sized: a worker still finishing a task of an earlier frame may read it.
  // Scaled to fixed point here, once, instead of per element (exact: a power of two).
  auto table = ForceTable(Tool_, Model_, ShellBinSpans(Shell_), f, n);
  for (BinForce& b : table) {
    b.fx *= kForceFixedScale;
    b.fy *= kForceFixedScale;
    b.fz *= kForceFixedScale;
    b.torque *= kForceFixedScale;
  }
  if (Table_.size() == table.size()) {
    for (size_t i = 0; i < table.size(); ++i) {
      StoreRelaxed(Table_[i].fx, table[i].fx);
      StoreRelaxed(Table_[i].fy, table[i].fy);
      StoreRelaxed(Table_[i].fz, table[i].fz);
      StoreRelaxed(Table_[i].torque, table[i].torque);
    }
  } else {
    Table_ = table; // the first cutting frame: no task has read it yet
  }
  TableFeed_ = f;
  TableSpeed_ = n;
}

std::vector<std::pair<EdgeKind, std::array<double, 2>>> ShellBinSpans(const PointShell& shell) {
  std::vector<std::pair<EdgeKind, std::array<double, 2>>> spans;
  for (const auto& fb : shell.ForceBins())
    spans.push_back({fb.kind, {fb.r, fb.dr}});
  return spans;
}

CpuEngine::~CpuEngine() {
  // A worker may still be finishing a task it lost (bmWorkerPool.h RunRedoable): join it before
  // the buffers it writes go.
  Pool_.Stop();
}

FrameResult CpuEngine::Step(const FrameInput& in) {
  const int T = Pool_.Threads();
  const uint32_t frameNo = ++Frame_;
  // The frame's context, held by the workers that run its tasks: one that was descheduled may
  // still be running a task after this frame (its results are not used), and must find
  // consistent geometry, so every index it forms stays inside the arrays.
  auto job = std::make_shared<PassJob>(
      PassJob{FrameGeometry(in, Shell_, Bone_), frameNo, in.envelopeRemoves, PrevWinner_});
  const FrameGeometry& G = job->G;
  if (G.cutting)
    UpdateForceTable(in.feedMmPerRev, in.speedRpm);
  const int nTasks = int(PrevWinner_.size());
  if (Incremental_ && Incremental_->Accepts(G)) {
    // One thread: one residency buffer, every task's winner thread 0; the frame's requests and
    // sums in task 0's partial.
    for (FramePartial& p : Partials_)
      p.Clear();
    std::fill(PrevWinner_.begin(), PrevWinner_.end(), uint8_t(0));
    IncrementalPass::Frame f{&G,
                             frameNo,
                             in.envelopeRemoves,
                             Table_.data(),
                             State_[0].words.data(),
                             State_[0].blockFrame.data()};
    Incremental_->Run(f, Bone_, Culling_, Partials_[0]);
  } else {
    Pool_.RunRedoable(nTasks,
                      std::make_shared<const WorkerPool::RedoableFn>(
                          [this, job](int task, int thread) { RunPassTask(*job, task, thread); }));
    for (int t = 0; t < nTasks; ++t)
      PrevWinner_[size_t(t)] = uint8_t(Pool_.Winner(t));
    if (Incremental_)
      Incremental_->FullPassRan(G);
  }

  const bool remove = G.remove;
  if (remove) {
    // One task per part: each applies, in task order, the requests for the voxels it owns.
    Pool_.Run(RemovalParts_, [&](int part, int) {
      Voxmap::RemovalTotals sum;
      std::vector<int64_t>& touched = Touched_[size_t(part)];
      touched.clear();
      for (int pi = 0; pi < nTasks; ++pi) {
        const RequestList& req =
            Partials_[size_t(pi * T + PrevWinner_[size_t(pi)])].removals[size_t(part)];
        if (req.Size() == 0)
          continue;
        const Voxmap::RemovalTotals r = Bone_.RemoveOwned(req.Data(), req.Size(), touched);
        sum.fill += r.fill;
        sum.voxels += r.voxels;
      }
      Bone_.MarkBricksChanged(touched);
      RemovalCounts_[size_t(part)] = sum;
    });
  }
  FramePartial total;
  for (int t = 0; t < nTasks; ++t)
    total.Add(Partials_[size_t(t * T + PrevWinner_[size_t(t)])]);
  if (remove)
    for (const Voxmap::RemovalTotals& r : RemovalCounts_) {
      total.removedFill += r.fill;
      total.removedVoxels += r.voxels;
    }
  FrameResult r = FrameResultOf(total, Bone_.VoxelVolume());
  FrameGeometry::UnturnLateral(r, in, Shell_);
  return r;
}

void CpuEngine::RunPassTask(const PassJob& job, int task, int thread) {
  const FrameGeometry& G = job.G;
  const uint32_t frameNo = job.frame;
  const bool cutting = G.cutting, remove = G.remove, envelope = job.envelopeRemoves;
  const Voxmap::Fill* fill = Bone_.FillData();
  const float* material = Bone_.MaterialData();
  const uint64_t* codes = Shell_.Codes().data();
  const std::array<float, 3>* an = Shell_.AreaNormals().data();
  const uint16_t* bins = Shell_.Bins().data();
  const float* deltas = Shell_.Deltas().data();
  const std::array<double, 2>* radial = Shell_.RadialDirs().data();
  const BinForce* table = Table_.data();
  const auto& blocks = Shell_.Blocks();
  const size_t T = size_t(Pool_.Threads());
  // The residency as the previous frame's winning run of this task left it, and this run's own.
  // One thread (no run of a task can overlap another): one buffer, updated in place.
  const ResidencyBuffer& prev =
      T == 1 ? State_[0] : State_[(job.prevWinner[size_t(task)] % T) * 2 + ((frameNo - 1) & 1)];
  ResidencyBuffer& cur = T == 1 ? State_[0] : State_[size_t(thread) * 2 + (frameNo & 1)];
  FramePartial& P = Partials_[size_t(task) * T + size_t(thread)];
  P.Clear();
  const int parts = RemovalParts_;
  RequestList* lists = P.removals.data();
  int64_t thrust = 0, torque = 0, fx = 0, fy = 0;
  int64_t visited = 0, engagedCount = 0, engagedCutting = 0, requested = 0;

  // The batch's voxels and bricks (on the stack, in L1).
  alignas(64) float gx[kBatch], gy[kBatch], gz[kBatch];
  alignas(64) int64_t vox[kBatch];
  alignas(64) int32_t brick[kBatch];
  Voxmap::RemovalRequest* ends[kMaxThreads]; // per removal part (at most one per thread)

  const int nBlocks = int(blocks.size());
  const int bEnd = std::min(nBlocks, (task + 1) * kBlocksPerTask);
  for (int bi = task * kBlocksPerTask; bi < bEnd; ++bi) {
    const ShellBlock& blk = blocks[size_t(bi)];
    if (!BlockVisible(blk, G, Bone_, Culling_))
      continue;
    // Whether the residency words of this block are the previous frame's (its elements were all
    // visited then); this frame visits them all.
    const bool fresh = LoadRelaxed(prev.blockFrame[size_t(bi)]) + 1 == frameNo;
    StoreRelaxed(cur.blockFrame[size_t(bi)], frameNo);
    const uint64_t* prevWords = prev.words.data() + blk.begin;
    uint64_t* curWords = cur.words.data() + blk.begin;
    for (uint32_t base = blk.begin; base < blk.end; base += kBatch) {
      const int n = int(std::min<uint32_t>(blk.end - base, kBatch));
      const uint32_t at = base - blk.begin;
      visited += n;
      // Pass A: the voxel of every element of the batch (Morton decode and the float
      // transform, vectorised), prefetching the fills that pass B reads: those of the elements
      // that do not stay engaged in their voxel (the voxel reads miss the cache: hiding that
      // latency is most of the frame's cost).
      ElementCoordsOf(codes + base, n, gx, gy, gz);
      G.VoxelsOf(gx, gy, gz, n, vox, brick);
      for (int q = 0; q < n; ++q)
        if (vox[q] >= 0 &&
            !PackedResidency::Stays(LoadRelaxed(prevWords[at + uint32_t(q)]), fresh, vox[q]))
          __builtin_prefetch(fill + vox[q]);
      if (remove)
        for (int p = 0; p < parts; ++p) {
          lists[p].Reserve(size_t(n));
          ends[p] = lists[p].End();
        }
      // Pass B: engagement (ElementResidency::Visit), removal requests, elemental forces.
      for (int q = 0; q < n; ++q) {
        const size_t e = base + size_t(q);
        const int64_t idx = vox[q];
        const bool stays =
            PackedResidency::Stays(LoadRelaxed(prevWords[at + uint32_t(q)]), fresh, idx);
        const bool engaged = idx >= 0 && (stays || LoadRelaxed(fill[idx]) > 0);
        StoreRelaxed(curWords[at + uint32_t(q)], PackedResidency::Word(idx, engaged));
        if (!engaged)
          continue;
        ++engagedCount;
        const uint64_t code = codes[e];
        if (remove && (envelope || ElementIsCutting(code)))
          if (const int32_t u = G.RemovalUnits(an[e]); u > 0) {
            // Into the last request of the voxel's owner when it is this voxel's (the clamped
            // decrement telescopes: same result), else a new one; no branch (the pattern is
            // data-dependent: mispredicted, it cost 5 % of the pass).
            const int p = Voxmap::LineOwner(idx, parts - 1);
            Voxmap::RemovalRequest* w = ends[p];
            const int32_t same = w[-1].voxel == idx;
            const int32_t before = w[-1].units & -same; // a mask: GCC branches on ?: here
            w -= same;
            *w = {idx, before + u, brick[q]};
            ends[p] = w + 1;
            requested += u;
          }
        if (cutting && ElementIsCutting(code)) {
          // Elemental force: delta x material x table[bin], the table in fixed-point units.
          ++engagedCutting;
          const double w = deltas[e] * (material ? material[idx] : 1.0f);
          const BinForce& tb = table[bins[e]];
          const double tfx = LoadRelaxed(tb.fx), tfy = LoadRelaxed(tb.fy);
          const double c = radial[e][0], s = radial[e][1];
          thrust += int64_t(w * LoadRelaxed(tb.fz));
          torque += int64_t(w * LoadRelaxed(tb.torque));
          fx += int64_t(w * (tfx * c - tfy * s));
          fy += int64_t(w * (tfx * s + tfy * c));
        }
      }
      if (remove)
        for (int p = 0; p < parts; ++p)
          lists[p].SetEnd(ends[p]);
    }
  }
  P.SetSums(thrust, torque, fx, fy, visited, engagedCount, engagedCutting, requested);
}

} // namespace bm
