#include "bmZhengEngine.h"

#include <algorithm>
#include <cmath>

#include "bmCpuEngine.h"
#include "bmFrameGeometry.h"
#include "bmMorton.h"

namespace bm {

ZhengEngine::ZhengEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell,
                         const ForceModel& model, int threads)
    : Bone_(bone), Tool_(tool), Shell_(shell), Model_(model), Tree_(bone), Pool_(threads),
      Buffer_(shell.Size()), Requests_(size_t(threads)), Engaged_(size_t(threads)),
      EngagedCut_(size_t(threads)), Visited_(size_t(threads)), State_(shell.Size()) {}

void ZhengEngine::SyncBone() {
  Tree_.CopyTo(Bone_);
}

FrameResult ZhengEngine::Step(const FrameInput& in) {
  FrameResult res;
  const uint32_t frameNo = ++Frame_;
  for (auto& r : Requests_)
    r.clear();
  std::fill(Engaged_.begin(), Engaged_.end(), 0);
  std::fill(EngagedCut_.begin(), EngagedCut_.end(), 0);
  std::fill(Visited_.begin(), Visited_.end(), 0);
  const FrameGeometry G(in, Shell_, Bone_);
  // Global bounding-box pre-check only (no block culling in the baseline).
  if (!G.ToolMeetsBone(Tool_, Bone_))
    return res;
  const bool cutting = G.cutting, remove = G.remove;
  const float* material = Bone_.MaterialData();
  const auto& codes = Shell_.Codes();
  const auto& an = Shell_.AreaNormals();
  const auto& bins = Shell_.Bins();
  const auto& deltas = Shell_.Deltas();
  const auto& fbins = Shell_.ForceBins();
  const auto& radial = Shell_.RadialDirs();
  const int n = int(codes.size());
  const int chunk = 4096;
  const int nChunks = (n + chunk - 1) / chunk;

  // Pass 1: per element, octree query, elemental force into the buffer.
  Pool_.Run(nChunks, [&](int task, int thread) {
    const int end = std::min(n, (task + 1) * chunk);
    for (int e = task * chunk; e < end; ++e) {
      auto& out = Buffer_[size_t(e)];
      out = {0, 0, 0, 0};
      const int64_t vidx = G.VoxelOf(ElementCoords(codes[size_t(e)]));
      ++Visited_[size_t(thread)];
      ElementResidency& st = State_[size_t(e)];
      if (vidx < 0) {
        st.Visit(frameNo, -1, 0);
        continue;
      }
      const auto v = Bone_.Coords(vidx);
      int level = 0;
      const int32_t leaf = Tree_.Find(v[0], v[1], v[2], level);
      if (!st.Visit(frameNo, vidx, Tree_.Value(leaf)))
        continue;
      ++Engaged_[size_t(thread)];
      if (remove && (in.envelopeRemoves || ElementIsCutting(codes[size_t(e)])))
        if (const int32_t units = G.RemovalUnits(an[size_t(e)]); units > 0)
          Requests_[size_t(thread)].push_back({uint32_t(e), units, v});
      if (cutting && ElementIsCutting(codes[size_t(e)])) {
        ++EngagedCut_[size_t(thread)];
        const ForceBin& fb = fbins[bins[size_t(e)]];
        const double mat = material ? material[vidx] : 1.0;
        const ElementForce f =
            Model_.Evaluate(Tool_, fb.kind, fb.r, in.feedMmPerRev, in.speedRpm, mat);
        const double w = deltas[size_t(e)];
        const double c = radial[size_t(e)][0], s = radial[size_t(e)][1];
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
      for (int q = 0; q < 4; ++q)
        s[q] += Buffer_[size_t(e)][q];
  });
  std::array<double, 4> total{0, 0, 0, 0};
  for (const auto& s : sums)
    for (int q = 0; q < 4; ++q)
      total[q] += s[q];

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
  FrameGeometry::UnturnLateral(res, in, Shell_);
  res.removedVolumeMm3 = double(res.removedFill) / Voxmap::kFull * Bone_.VoxelVolume();
  res.sweptVolumeMm3 = double(requested) / Voxmap::kFull * Bone_.VoxelVolume();
  return res;
}

} // namespace bm
