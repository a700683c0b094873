#include "bmCpuEngine.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include <Eigen/Geometry>

#include "bmFrameGeometry.h"
#include "bmMorton.h"

namespace bm {

void FramePartial::Clear() {
  thrust = torque = fx = fy = 0;
  visited = engaged = engagedCutting = requested = 0;
  removedFill = removedVoxels = 0;
  for (auto& r : removals)
    r.clear();
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
ElementResidency LoadResidency(const ElementResidency& r) {
  ElementResidency o;
  o.voxel = LoadRelaxed(r.voxel);
  o.frame = LoadRelaxed(r.frame);
  o.engaged = LoadRelaxed(r.engaged);
  return o;
}
void StoreResidency(ElementResidency& r, const ElementResidency& v) {
  StoreRelaxed(r.voxel, v.voxel);
  StoreRelaxed(r.frame, v.frame);
  StoreRelaxed(r.engaged, v.engaged);
}

} // namespace

double MaxRemovalUnits(const Eigen::Vector3d& d, double voxelMm, double unitsPerMm3) {
  // Projected area of a voxel along d times |d|: h^2 (|dx| + |dy| + |dz|).
  const double swept = voxelMm * voxelMm * (std::abs(d(0)) + std::abs(d(1)) + std::abs(d(2)));
  return std::min(swept * unitsPerMm3, double(Voxmap::kFull));
}

FrameResult SumPartials(const std::vector<FramePartial>& parts, double voxelVolume) {
  FrameResult r;
  int64_t fx = 0, fy = 0, requested = 0;
  for (const auto& p : parts) {
    r.thrustFixed += p.thrust;
    r.torqueFixed += p.torque;
    fx += p.fx;
    fy += p.fy;
    r.visitedElements += p.visited;
    r.engagedElements += p.engaged;
    r.engagedCutting += p.engagedCutting;
    r.removedFill += p.removedFill;
    r.removedVoxels += p.removedVoxels;
    requested += p.requested;
  }
  r.thrustN = double(r.thrustFixed) / kForceFixedScale;
  r.torqueNmm = double(r.torqueFixed) / kForceFixedScale;
  r.forceTool = {double(fx) / kForceFixedScale, double(fy) / kForceFixedScale, r.thrustN};
  r.removedVolumeMm3 = double(r.removedFill) / Voxmap::kFull * voxelVolume;
  r.sweptVolumeMm3 = double(requested) / Voxmap::kFull * voxelVolume;
  return r;
}

CpuEngine::CpuEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell,
                     const ForceModel& model, int threads, CullingOptions culling)
    : Bone_(bone), Tool_(tool), Shell_(shell), Model_(model), Culling_(culling), Pool_(threads),
      Partials_(NumTasks(shell) * size_t(Pool_.Threads())),
      State_(Pool_.Threads() == 1 ? 1 : 2 * size_t(Pool_.Threads()),
             std::vector<ElementResidency>(shell.Size())),
      PrevWinner_(NumTasks(shell), 0),
      VoxelScratch_(size_t(Pool_.Threads()), std::vector<int64_t>(kBatch)),
      BrickScratch_(size_t(Pool_.Threads()), std::vector<int32_t>(kBatch)) {
  while (RemovalParts_ < Pool_.Threads())
    RemovalParts_ *= 2;
  for (FramePartial& p : Partials_)
    p.removals.resize(size_t(RemovalParts_));
  RemovalCounts_.resize(size_t(RemovalParts_));
  Touched_.resize(size_t(RemovalParts_));
  Pool_.ReserveRedoable(int(NumTasks(shell)));
}

size_t CpuEngine::NumTasks(const PointShell& shell) {
  return (shell.Blocks().size() + kBlocksPerTask - 1) / kBlocksPerTask;
}

void CpuEngine::UpdateForceTable(double f, double n) {
  if (f == TableFeed_ && n == TableSpeed_)
    return;
  // In place once sized: a worker still finishing a task of an earlier frame may read it.
  const auto table = ForceTable(Tool_, Model_, ShellBinSpans(Shell_), f, n);
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
  Pool_.RunRedoable(nTasks,
                    std::make_shared<const WorkerPool::RedoableFn>(
                        [this, job](int task, int thread) { RunPassTask(*job, task, thread); }));
  for (int t = 0; t < nTasks; ++t)
    PrevWinner_[size_t(t)] = uint8_t(Pool_.Winner(t));

  const bool remove = G.remove;
  if (remove) {
    // One task per part: each applies, in task order, the requests for the voxels it owns.
    Pool_.Run(RemovalParts_, [&](int part, int) {
      Voxmap::RemovalTotals sum;
      std::vector<int64_t>& touched = Touched_[size_t(part)];
      touched.clear();
      for (int pi = 0; pi < nTasks; ++pi) {
        const auto& req =
            Partials_[size_t(pi * T + PrevWinner_[size_t(pi)])].removals[size_t(part)];
        if (req.empty())
          continue;
        const Voxmap::RemovalTotals r = Bone_.RemoveOwned(req.data(), req.size(), touched);
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
  FrameResult r = SumPartials({total}, Bone_.VoxelVolume());
  FrameGeometry::UnturnLateral(r, in, Shell_);
  return r;
}

void CpuEngine::RunPassTask(const PassJob& job, int task, int thread) {
  const FrameGeometry& G = job.G;
  const uint32_t frameNo = job.frame;
  const bool cutting = G.cutting, remove = G.remove;
  const Eigen::Vector3d& d = G.motionTool;
  const Voxmap::Fill* fill = Bone_.FillData();
  const float* material = Bone_.MaterialData();
  const auto& codes = Shell_.Codes();
  const auto& an = Shell_.AreaNormals();
  const auto& bins = Shell_.Bins();
  const auto& deltas = Shell_.Deltas();
  const auto& blocks = Shell_.Blocks();
  const auto& radial = Shell_.RadialDirs();
  const size_t T = size_t(Pool_.Threads());
  // The residency as the previous frame's winning run of this task left it, and this run's own.
  // One thread (no run of a task can overlap another): one buffer, updated in place.
  const ElementResidency* prev =
      T == 1 ? State_[0].data()
             : State_[(job.prevWinner[size_t(task)] % T) * 2 + ((frameNo - 1) & 1)].data();
  ElementResidency* cur =
      T == 1 ? State_[0].data() : State_[size_t(thread) * 2 + (frameNo & 1)].data();
  FramePartial& P = Partials_[size_t(task) * T + size_t(thread)];
  P.Clear();

  auto blockVisible = [&](const ShellBlock& blk) {
    if (Culling_.motion && !blk.hasCutting) {
      double up = 0;
      for (int a = 0; a < 3; ++a)
        up += std::max(blk.nLo[a] * d(a), blk.nHi[a] * d(a));
      if (up <= 0 || !remove)
        return false;
    }
    if (!Culling_.blocks)
      return true;
    std::array<int, 3> lo, hi;
    G.VoxelBox(blk.lo, blk.hi, lo, hi);
    return Bone_.AnyBoneIn(lo, hi);
  };

  const int nBlocks = int(blocks.size());
  const int bEnd = std::min(nBlocks, (task + 1) * kBlocksPerTask);
  for (int bi = task * kBlocksPerTask; bi < bEnd; ++bi) {
    const ShellBlock& blk = blocks[size_t(bi)];
    if (!blockVisible(blk))
      continue;
    // Pass A: voxel of every element of the block, prefetching the fills that pass B reads
    // (the voxel reads miss the cache: hiding that latency is most of the frame's cost). An
    // element that stays engaged in its voxel does not read the fill (ElementResidency::Stays).
    for (uint32_t base = blk.begin; base < blk.end; base += kBatch) {
      const uint32_t end = std::min(blk.end, base + kBatch);
      int64_t* vox = VoxelScratch_[size_t(thread)].data();
      int32_t* brick = BrickScratch_[size_t(thread)].data();
      alignas(64) float gx[kBatch], gy[kBatch], gz[kBatch];
      ElementCoordsOf(codes.data() + base, int(end - base), gx, gy, gz);
      G.VoxelsOf(gx, gy, gz, int(end - base), vox, brick);
      for (uint32_t e = base; e < end; ++e) {
        const int64_t idx = vox[e - base];
        if (idx >= 0 && !LoadResidency(prev[e]).Stays(frameNo, idx))
          __builtin_prefetch(fill + idx);
      }
      // Pass B: engagement, removal requests, elemental forces.
      for (uint32_t e = base; e < end; ++e) {
        const int64_t idx = vox[e - base];
        ++P.visited;
        ElementResidency st = LoadResidency(prev[e]);
        const bool engaged = st.Visit(
            frameNo, idx, idx >= 0 && !st.Stays(frameNo, idx) ? LoadRelaxed(fill[idx]) : 0);
        StoreResidency(cur[e], st);
        if (!engaged)
          continue;
        ++P.engaged;
        if (remove && (job.envelopeRemoves || ElementIsCutting(codes[e]))) {
          if (const int32_t units = G.RemovalUnits(an[e]); units > 0) {
            // Consecutive elements often share a voxel: one request per run (same result,
            // since the clamped decrement telescopes).
            auto& list = P.removals[size_t(Voxmap::LineOwner(idx, RemovalParts_ - 1))];
            if (!list.empty() && list.back().voxel == idx)
              list.back().units += units;
            else
              list.push_back({idx, units, brick[e - base]});
            P.requested += units;
          }
        }
        const uint64_t code = codes[e];
        if (cutting && ElementIsCutting(code)) {
          ++P.engagedCutting;
          const uint16_t bin = bins[e];
          const double w = deltas[e] * (material ? material[idx] : 1.0f);
          const BinForce& tb = Table_[bin];
          const double tfx = LoadRelaxed(tb.fx), tfy = LoadRelaxed(tb.fy);
          const double c = radial[e][0], s = radial[e][1];
          P.thrust += int64_t(w * LoadRelaxed(tb.fz) * kForceFixedScale);
          P.torque += int64_t(w * LoadRelaxed(tb.torque) * kForceFixedScale);
          P.fx += int64_t(w * (tfx * c - tfy * s) * kForceFixedScale);
          P.fy += int64_t(w * (tfx * s + tfy * c) * kForceFixedScale);
        }
      }
    }
  }
}

} // namespace bm
