#include "bmCpuEngine.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "bmFrameGeometry.h"
#include "bmMorton.h"

namespace bm {

void FramePartial::Clear() {
  thrust = torque = fx = fy = 0;
  visited = engaged = engagedCutting = requested = 0;
  removedFill = removedVoxels = 0;
  removals.clear();
}

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
      Partials_(size_t(threads)), State_(shell.Size()),
      VoxelScratch_(size_t(threads), std::vector<int64_t>(kBatch)) {}

void CpuEngine::UpdateForceTable(double f, double n) {
  if (f == TableFeed_ && n == TableSpeed_)
    return;
  Table_ = ForceTable(Tool_, Model_, ShellBinSpans(Shell_), f, n);
  TableFeed_ = f;
  TableSpeed_ = n;
}

std::vector<std::pair<EdgeKind, std::array<double, 2>>> ShellBinSpans(const PointShell& shell) {
  std::vector<std::pair<EdgeKind, std::array<double, 2>>> spans;
  for (const auto& fb : shell.ForceBins())
    spans.push_back({fb.kind, {fb.r, fb.dr}});
  return spans;
}

FrameResult CpuEngine::Step(const FrameInput& in) {
  for (auto& p : Partials_)
    p.Clear();
  const uint32_t frameNo = ++Frame_;
  const FrameGeometry G(in, Shell_, Bone_);
  if (G.cutting)
    UpdateForceTable(in.feedMmPerRev, in.speedRpm);
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
  const int chunk = 16; // blocks per task
  Pool_.Run((nBlocks + chunk - 1) / chunk, [&](int task, int thread) {
    FramePartial& P = Partials_[size_t(thread)];
    const int bEnd = std::min(nBlocks, (task + 1) * chunk);
    for (int bi = task * chunk; bi < bEnd; ++bi) {
      const ShellBlock& blk = blocks[size_t(bi)];
      if (!blockVisible(blk))
        continue;
      // Pass A: voxel of every element of the block, prefetching the fills (the voxel reads
      // miss the cache: hiding that latency is most of the frame's cost).
      for (uint32_t base = blk.begin; base < blk.end; base += kBatch) {
        const uint32_t end = std::min(blk.end, base + kBatch);
        int64_t* vox = VoxelScratch_[size_t(thread)].data();
        for (uint32_t e = base; e < end; ++e) {
          const int64_t idx = G.VoxelOf(ElementCoords(codes[e]));
          if (idx >= 0)
            __builtin_prefetch(fill + idx);
          vox[e - base] = idx;
        }
        // Pass B: engagement, removal requests, elemental forces.
        for (uint32_t e = base; e < end; ++e) {
          const int64_t idx = vox[e - base];
          ++P.visited;
          if (!State_[e].Visit(frameNo, idx, idx >= 0 ? fill[idx] : 0))
            continue;
          ++P.engaged;
          if (remove && (in.envelopeRemoves || ElementIsCutting(codes[e]))) {
            if (const int32_t units = G.RemovalUnits(an[e]); units > 0) {
              // Consecutive elements often share a voxel: one request per run (same result,
              // since the clamped decrement telescopes).
              if (!P.removals.empty() && P.removals.back().first == idx)
                P.removals.back().second += units;
              else
                P.removals.emplace_back(idx, units);
              P.requested += units;
            }
          }
          const uint64_t code = codes[e];
          if (cutting && ElementIsCutting(code)) {
            ++P.engagedCutting;
            const uint16_t bin = bins[e];
            const double w = deltas[e] * (material ? material[idx] : 1.0f);
            const BinForce& t = Table_[bin];
            const double c = radial[e][0], s = radial[e][1];
            P.thrust += int64_t(w * t.fz * kForceFixedScale);
            P.torque += int64_t(w * t.torque * kForceFixedScale);
            P.fx += int64_t(w * (t.fx * c - t.fy * s) * kForceFixedScale);
            P.fy += int64_t(w * (t.fx * s + t.fy * c) * kForceFixedScale);
          }
        }
      }
    }
  });

  if (remove) {
    Pool_.Run(int(Partials_.size()), [&](int task, int thread) {
      (void)thread;
      FramePartial& P = Partials_[size_t(task)];
      for (const auto& [idx, units] : P.removals) {
        bool voided = false;
        P.removedFill += Bone_.Remove(idx, units, voided);
        P.removedVoxels += voided;
      }
    });
  }
  FrameResult r = SumPartials(Partials_, Bone_.VoxelVolume());
  FrameGeometry::UnturnLateral(r, in, Shell_);
  return r;
}

} // namespace bm
