#include "bmZhengEngine.h"

#include <algorithm>
#include <cmath>

#include "bmCpuEngine.h"
#include "bmMorton.h"

namespace bm {

ZhengEngine::ZhengEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell, const ForceModel& model,
                         int threads)
    : Bone_(bone), Tool_(tool), Shell_(shell), Model_(model), Tree_(bone), Pool_(threads),
      Buffer_(shell.Size()), Requests_(size_t(threads)), Engaged_(size_t(threads)), EngagedCut_(size_t(threads)),
      Visited_(size_t(threads)), State_(shell.Size()) {}

void ZhengEngine::SyncBone() { Tree_.CopyTo(Bone_); }

FrameResult ZhengEngine::Step(const FrameInput& in) {
  FrameResult res;
  const uint32_t frameNo = ++Frame_;
  for (auto& r : Requests_) r.clear();
  std::fill(Engaged_.begin(), Engaged_.end(), 0);
  std::fill(EngagedCut_.begin(), EngagedCut_.end(), 0);
  std::fill(Visited_.begin(), Visited_.end(), 0);
  const bool cutting = in.speedRpm > 0 && in.feedMmPerRev > 0;
  const double hs = Shell_.Spacing(), hv = Bone_.Spacing();
  Eigen::Matrix3d rot = in.rotation;
  const Eigen::Vector3d so(Shell_.Origin()[0], Shell_.Origin()[1], Shell_.Origin()[2]);
  const Eigen::Vector3d vo(Bone_.Origin()[0], Bone_.Origin()[1], Bone_.Origin()[2]);

  // Global bounding-box pre-check.
  {
    const double R = Tool_.OuterRadius();
    const auto zr = Tool_.AxialRange();
    Box3 tb{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
    for (int c = 0; c < 8; ++c) {
      Eigen::Vector3d p((c & 1) ? R : -R, (c & 2) ? R : -R, (c & 4) ? zr[1] : zr[0]);
      Eigen::Vector3d w = rot * p + in.position;
      for (int a = 0; a < 3; ++a) {
        tb.lo[a] = std::min(tb.lo[a], w(a));
        tb.hi[a] = std::max(tb.hi[a], w(a));
      }
    }
    if (!tb.Intersects(Bone_.Bounds())) return res;
  }

  const Eigen::Matrix3d A = rot * (hs / hv);
  const Eigen::Vector3d b = (rot * so + in.position - vo) / hv;
  const Eigen::Vector3d d = rot.transpose() * in.motion;
  const double unitsPerMm3 = Voxmap::kFull / Bone_.VoxelVolume();
  const bool remove = in.removeMaterial && d.squaredNorm() > 0;
  const double maxUnits = MaxRemovalUnits(d, hv, unitsPerMm3);
  const auto dims = Bone_.Dims();
  const float* material = Bone_.MaterialData();
  const auto& codes = Shell_.Codes();
  const auto& an = Shell_.AreaNormals();
  const auto& bins = Shell_.Bins();
  const auto& deltas = Shell_.Deltas();
  const auto& fbins = Shell_.ForceBins();
  const float Af[9] = {float(A(0, 0)), float(A(0, 1)), float(A(0, 2)), float(A(1, 0)), float(A(1, 1)),
                       float(A(1, 2)), float(A(2, 0)), float(A(2, 1)), float(A(2, 2))};
  const float bf[3] = {float(b(0)), float(b(1)), float(b(2))};
  const int n = int(codes.size());
  const int chunk = 4096;
  const int nChunks = (n + chunk - 1) / chunk;

  // Pass 1: per element, octree query, elemental force into the buffer.
  Pool_.Run(nChunks, [&](int task, int thread) {
    const int end = std::min(n, (task + 1) * chunk);
    for (int e = task * chunk; e < end; ++e) {
      auto& out = Buffer_[size_t(e)];
      out = {0, 0, 0, 0};
      const auto ijk = ElementCoords(codes[size_t(e)]);
      const float x = float(ijk[0]), y = float(ijk[1]), z = float(ijk[2]);
      const int vi = int(std::floor(Af[0] * x + Af[1] * y + Af[2] * z + bf[0] + 0.5f));
      const int vj = int(std::floor(Af[3] * x + Af[4] * y + Af[5] * z + bf[1] + 0.5f));
      const int vk = int(std::floor(Af[6] * x + Af[7] * y + Af[8] * z + bf[2] + 0.5f));
      ++Visited_[size_t(thread)];
      ElementResidency& st = State_[size_t(e)];
      if (vi < 0 || vj < 0 || vk < 0 || vi >= dims[0] || vj >= dims[1] || vk >= dims[2]) {
        st.Visit(frameNo, -1, 0);
        continue;
      }
      int level = 0;
      const int32_t leaf = Tree_.Find(vi, vj, vk, level);
      const int64_t vidx = vi + int64_t(dims[0]) * (vj + int64_t(dims[1]) * vk);
      if (!st.Visit(frameNo, vidx, Tree_.Value(leaf))) continue;
      ++Engaged_[size_t(thread)];
      if (remove) {
        const auto& nrm = an[size_t(e)];
        const double vol = nrm[0] * d(0) + nrm[1] * d(1) + nrm[2] * d(2);
        if (vol > 0) {
          const int32_t units = int32_t(std::min(vol * unitsPerMm3, maxUnits) + 0.5);
          if (units > 0) Requests_[size_t(thread)].push_back({uint32_t(e), units, {vi, vj, vk}});
        }
      }
      if (cutting && ElementIsCutting(codes[size_t(e)])) {
        ++EngagedCut_[size_t(thread)];
        const ForceBin& fb = fbins[bins[size_t(e)]];
        const int64_t idx = vi + int64_t(dims[0]) * (vj + int64_t(dims[1]) * vk);
        const double mat = material ? material[idx] : 1.0;
        const ElementForce f = Model_.Evaluate(Tool_, fb.kind, fb.r, in.feedMmPerRev, in.speedRpm, mat);
        const double w = deltas[size_t(e)];
        const double px = so(0) + hs * ijk[0], py = so(1) + hs * ijk[1];
        const double rho = std::sqrt(px * px + py * py);
        const double c = rho > 0 ? px / rho : 1.0, s = rho > 0 ? py / rho : 0.0;
        out = {w * (f.fx * c - f.fy * s), w * (f.fx * s + f.fy * c), w * f.fz, -w * fb.r * f.fy};
      }
    }
  });

  // Pass 2: reduction of the buffer, chunk sums in a fixed order.
  std::vector<std::array<double, 4>> sums(size_t(nChunks), {0, 0, 0, 0});
  Pool_.Run(nChunks, [&](int task, int) {
    const int end = std::min(n, (task + 1) * chunk);
    auto& s = sums[size_t(task)];
    for (int e = task * chunk; e < end; ++e)
      for (int q = 0; q < 4; ++q) s[q] += Buffer_[size_t(e)][q];
  });
  std::array<double, 4> total{0, 0, 0, 0};
  for (const auto& s : sums)
    for (int q = 0; q < 4; ++q) total[q] += s[q];

  // Pass 3: removal. Leaves are refined to voxels first (one thread), then cut in parallel.
  int64_t requested = 0;
  for (auto& list : Requests_)
    for (const auto& r : list) {
      Tree_.Refine(r.ijk[0], r.ijk[1], r.ijk[2]);
      requested += r.units;
    }
  std::vector<int64_t> removedFill(Requests_.size(), 0), removedVoxels(Requests_.size(), 0);
  Pool_.Run(int(Requests_.size()), [&](int task, int) {
    for (const auto& r : Requests_[size_t(task)]) {
      int level = 0;
      const int32_t leaf = Tree_.Find(r.ijk[0], r.ijk[1], r.ijk[2], level);
      bool voided = false;
      removedFill[size_t(task)] += Tree_.Remove(leaf, r.units, voided);
      removedVoxels[size_t(task)] += voided;
    }
  });

  res.forceTool = {total[0], total[1], total[2]};
  res.thrustN = total[2];
  res.torqueNmm = total[3];
  res.thrustFixed = int64_t(total[2] * kForceFixedScale);
  res.torqueFixed = int64_t(total[3] * kForceFixedScale);
  for (size_t t = 0; t < Requests_.size(); ++t) {
    res.visitedElements += Visited_[t];
    res.engagedElements += Engaged_[t];
    res.engagedCutting += EngagedCut_[t];
    res.removedFill += removedFill[t];
    res.removedVoxels += removedVoxels[t];
  }
  res.removedVolumeMm3 = double(res.removedFill) / Voxmap::kFull * Bone_.VoxelVolume();
  res.sweptVolumeMm3 = double(requested) / Voxmap::kFull * Bone_.VoxelVolume();
  return res;
}

} // namespace bm
