#include "bmCpuEngine.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

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

CpuEngine::CpuEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell, const ForceModel& model,
                     int threads, CullingOptions culling)
    : Bone_(bone), Tool_(tool), Shell_(shell), Model_(model), Culling_(culling), Pool_(threads),
      Partials_(size_t(threads)), State_(shell.Size()),
      VoxelScratch_(size_t(threads), std::vector<int64_t>(kBatch)) {}

void CpuEngine::UpdateForceTable(double f, double n) {
  if (f == TableFeed_ && n == TableSpeed_) return;
  const auto& bins = Shell_.ForceBins();
  Table_.resize(bins.size());
  for (size_t b = 0; b < bins.size(); ++b) {
    ElementForce e = Model_.Evaluate(Tool_, bins[b].kind, bins[b].r, f, n);
    Table_[b] = {e.fx, e.fy, e.fz};
  }
  TableFeed_ = f;
  TableSpeed_ = n;
}

FrameResult CpuEngine::Step(const FrameInput& in) {
  for (auto& p : Partials_) p.Clear();
  const uint32_t frameNo = ++Frame_;
  const bool cutting = in.speedRpm > 0 && in.feedMmPerRev > 0;
  if (cutting) UpdateForceTable(in.feedMmPerRev, in.speedRpm);

  // Tool grid (i,j,k) -> voxmap grid coordinates: g = A ijk + b.
  Eigen::Matrix3d rot = in.rotation;
  if (Shell_.Mode() == LipMode::Instantaneous) rot = rot * Eigen::AngleAxisd(in.spindleAngle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double hs = Shell_.Spacing(), hv = Bone_.Spacing();
  const Eigen::Vector3d so(Shell_.Origin()[0], Shell_.Origin()[1], Shell_.Origin()[2]);
  const Eigen::Vector3d vo(Bone_.Origin()[0], Bone_.Origin()[1], Bone_.Origin()[2]);
  const Eigen::Matrix3d A = rot * (hs / hv);
  const Eigen::Vector3d b = (rot * so + in.position - vo) / hv;
  // Removal: fill units per mm^3 of swept volume; the motion in the tool frame.
  const Eigen::Vector3d d = rot.transpose() * in.motion;
  const double unitsPerMm3 = Voxmap::kFull / Bone_.VoxelVolume();
  const bool remove = in.removeMaterial && d.squaredNorm() > 0;
  // An element cuts only the voxel it lies in, so it may take at most what that voxel's own
  // cross-section sweeps this frame (binds only when the shell is coarser than the voxmap: then
  // columns between elements stay, and the summary's removed volume falls short of the swept).
  const double maxUnits = MaxRemovalUnits(d, hv, unitsPerMm3);
  const auto dims = Bone_.Dims();
  const Voxmap::Fill* fill = Bone_.FillData();
  const float* material = Bone_.MaterialData();
  const auto& codes = Shell_.Codes();
  const auto& an = Shell_.AreaNormals();
  const auto& bins = Shell_.Bins();
  const auto& deltas = Shell_.Deltas();
  const auto& fbins = Shell_.ForceBins();
  const auto& blocks = Shell_.Blocks();
  const auto& radial = Shell_.RadialDirs();
  const float Af[9] = {float(A(0, 0)), float(A(0, 1)), float(A(0, 2)), float(A(1, 0)), float(A(1, 1)),
                       float(A(1, 2)), float(A(2, 0)), float(A(2, 1)), float(A(2, 2))};
  const float bf[3] = {float(b(0)), float(b(1)), float(b(2))};

  auto blockVisible = [&](const ShellBlock& blk) {
    if (Culling_.motion && !blk.hasCutting) {
      double up = 0;
      for (int a = 0; a < 3; ++a) up += std::max(blk.nLo[a] * d(a), blk.nHi[a] * d(a));
      if (up <= 0 || !remove) return false;
    }
    if (!Culling_.blocks) return true;
    std::array<int, 3> lo{INT32_MAX, INT32_MAX, INT32_MAX}, hi{INT32_MIN, INT32_MIN, INT32_MIN};
    for (int c = 0; c < 8; ++c) {
      Eigen::Vector3d p((c & 1) ? blk.hi[0] : blk.lo[0], (c & 2) ? blk.hi[1] : blk.lo[1], (c & 4) ? blk.hi[2] : blk.lo[2]);
      Eigen::Vector3d g = (rot * p + in.position - vo) / hv;
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], int(std::floor(g(a) + 0.5)));
        hi[a] = std::max(hi[a], int(std::floor(g(a) + 0.5)));
      }
    }
    return Bone_.AnyBoneIn(lo, hi);
  };

  const int nBlocks = int(blocks.size());
  const int chunk = 16; // blocks per task
  Pool_.Run((nBlocks + chunk - 1) / chunk, [&](int task, int thread) {
    FramePartial& P = Partials_[size_t(thread)];
    const int bEnd = std::min(nBlocks, (task + 1) * chunk);
    for (int bi = task * chunk; bi < bEnd; ++bi) {
      const ShellBlock& blk = blocks[size_t(bi)];
      if (!blockVisible(blk)) continue;
      // Pass A: voxel of every element of the block, prefetching the fills (the voxel reads
      // miss the cache: hiding that latency is most of the frame's cost).
      for (uint32_t base = blk.begin; base < blk.end; base += kBatch) {
        const uint32_t end = std::min(blk.end, base + kBatch);
        int64_t* vox = VoxelScratch_[size_t(thread)].data();
        for (uint32_t e = base; e < end; ++e) {
          const auto ijk = ElementCoords(codes[e]);
          const float x = float(ijk[0]), y = float(ijk[1]), z = float(ijk[2]);
          const float gx = Af[0] * x + Af[1] * y + Af[2] * z + bf[0];
          const float gy = Af[3] * x + Af[4] * y + Af[5] * z + bf[1];
          const float gz = Af[6] * x + Af[7] * y + Af[8] * z + bf[2];
          const int vi = int(std::floor(gx + 0.5f)), vj = int(std::floor(gy + 0.5f)), vk = int(std::floor(gz + 0.5f));
          int64_t idx = -1;
          if (vi >= 0 && vj >= 0 && vk >= 0 && vi < dims[0] && vj < dims[1] && vk < dims[2]) {
            idx = vi + int64_t(dims[0]) * (vj + int64_t(dims[1]) * vk);
            __builtin_prefetch(fill + idx);
          }
          vox[e - base] = idx;
        }
        // Pass B: engagement, removal requests, elemental forces.
        for (uint32_t e = base; e < end; ++e) {
          const int64_t idx = vox[e - base];
          ++P.visited;
          if (!State_[e].Visit(frameNo, idx, idx >= 0 ? fill[idx] : 0)) continue;
          ++P.engaged;
          if (remove) {
            const auto& n = an[e];
            const double vol = n[0] * d(0) + n[1] * d(1) + n[2] * d(2);
            if (vol > 0) {
              const int32_t units = int32_t(std::min(vol * unitsPerMm3, maxUnits) + 0.5);
              if (units > 0) {
                // Consecutive elements often share a voxel: one request per run (same result,
                // since the clamped decrement telescopes).
                if (!P.removals.empty() && P.removals.back().first == idx) P.removals.back().second += units;
                else P.removals.emplace_back(idx, units);
                P.requested += units;
              }
            }
          }
          const uint64_t code = codes[e];
          if (cutting && ElementIsCutting(code)) {
            ++P.engagedCutting;
            const uint16_t bin = bins[e];
            const double w = deltas[e] * (material ? material[idx] : 1.0f);
            const auto& t = Table_[bin];
            const double c = radial[e][0], s = radial[e][1];
            P.thrust += int64_t(w * t[2] * kForceFixedScale);
            P.torque += int64_t(-w * fbins[bin].r * t[1] * kForceFixedScale);
            P.fx += int64_t(w * (t[0] * c - t[1] * s) * kForceFixedScale);
            P.fy += int64_t(w * (t[0] * s + t[1] * c) * kForceFixedScale);
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
  // Lateral forces were summed in the spindle-turned frame; report them in the tool frame.
  if (Shell_.Mode() == LipMode::Instantaneous) {
    const double c = std::cos(in.spindleAngle), s = std::sin(in.spindleAngle);
    const double fx = r.forceTool(0), fy = r.forceTool(1);
    r.forceTool(0) = c * fx - s * fy;
    r.forceTool(1) = s * fx + c * fy;
  }
  return r;
}

} // namespace bm
