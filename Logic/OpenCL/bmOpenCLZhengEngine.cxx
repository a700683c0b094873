#include "bmOpenCLZhengEngine.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "bmCpuEngine.h"
#include "bmElementResidency.h"
#include "bmFrameGeometry.h"
#include "bmKernelSources.h"

namespace bm {

namespace {
constexpr int kSums = 4, kRemovalSums = 2, kTerms = 10, kChunk = 4096;
} // namespace

// As OctreeVoxmap::Build: uniform cubes collapse into one leaf, children stored as runs of 8.
int32_t OpenCLZhengEngine::Build(int level, int i0, int j0, int k0) {
  const auto& dims = Bone_.Dims();
  if (i0 >= dims[0] || j0 >= dims[1] || k0 >= dims[2]) {
    Nodes_.push_back({{-1, 0}});
    return int32_t(Nodes_.size() - 1);
  }
  if (level == 0) {
    Nodes_.push_back({{-1, Bone_.GetFill(Bone_.Index(i0, j0, k0))}});
    return int32_t(Nodes_.size() - 1);
  }
  const int half = 1 << (level - 1);
  int32_t kids[8];
  for (int c = 0; c < 8; ++c)
    kids[c] = Build(level - 1, i0 + ((c & 1) ? half : 0), j0 + ((c & 2) ? half : 0),
                    k0 + ((c & 4) ? half : 0));
  bool uniform = true;
  for (int c = 0; c < 8 && uniform; ++c)
    uniform = Nodes_[size_t(kids[c])].s[0] < 0 &&
              Nodes_[size_t(kids[c])].s[1] == Nodes_[size_t(kids[0])].s[1];
  if (uniform) {
    const cl_int value = Nodes_[size_t(kids[0])].s[1];
    Nodes_.resize(size_t(kids[0]));
    Nodes_.push_back({{-1, value}});
    return int32_t(Nodes_.size() - 1);
  }
  const int32_t first = int32_t(Nodes_.size());
  for (int c = 0; c < 8; ++c)
    Nodes_.push_back(Nodes_[size_t(kids[c])]);
  Nodes_.push_back({{first, 0}});
  return int32_t(Nodes_.size() - 1);
}

void OpenCLZhengEngine::Refine(int i, int j, int k) {
  int32_t node = 0;
  int level = Levels_;
  while (Nodes_[size_t(node)].s[0] >= 0) {
    --level;
    const int c = ((i >> level) & 1) | (((j >> level) & 1) << 1) | (((k >> level) & 1) << 2);
    node = Nodes_[size_t(node)].s[0] + c;
  }
  while (level > 0) {
    const int32_t first = int32_t(Nodes_.size());
    const cl_int value = Nodes_[size_t(node)].s[1];
    for (int c = 0; c < 8; ++c)
      Nodes_.push_back({{-1, value}});
    Nodes_[size_t(node)].s[0] = first;
    if (size_t(node) < Uploaded_)
      Dirty_.push_back(node);
    --level;
    const int c = ((i >> level) & 1) | (((j >> level) & 1) << 1) | (((k >> level) & 1) << 2);
    node = first + c;
  }
}

void OpenCLZhengEngine::UploadTree() {
  auto& q = Rt_.queue;
  if (Nodes_.size() > Capacity_) {
    // Grow: copy the device's nodes (their voxel leaves hold the cut state) into a larger buffer.
    const size_t cap = std::max(Nodes_.size(), 2 * Capacity_);
    cl::Buffer bigger(Rt_.context, CL_MEM_READ_WRITE, cap * sizeof(cl_int2));
    if (Uploaded_ > 0)
      q.enqueueCopyBuffer(NodesDev_, bigger, 0, 0, Uploaded_ * sizeof(cl_int2));
    Rt_.deviceBytes += (cap - Capacity_) * sizeof(cl_int2);
    NodesDev_ = bigger;
    Capacity_ = cap;
  }
  // Split nodes: only their child index changed (they were coarse leaves, never cut).
  std::sort(Dirty_.begin(), Dirty_.end());
  Dirty_.erase(std::unique(Dirty_.begin(), Dirty_.end()), Dirty_.end());
  for (size_t s = 0; s < Dirty_.size();) {
    size_t e = s + 1;
    while (e < Dirty_.size() && Dirty_[e] == Dirty_[e - 1] + 1)
      ++e;
    q.enqueueWriteBuffer(NodesDev_, CL_FALSE, size_t(Dirty_[s]) * sizeof(cl_int2),
                         (e - s) * sizeof(cl_int2), &Nodes_[size_t(Dirty_[s])]);
    s = e;
  }
  Dirty_.clear();
  if (Nodes_.size() > Uploaded_)
    q.enqueueWriteBuffer(NodesDev_, CL_FALSE, Uploaded_ * sizeof(cl_int2),
                         (Nodes_.size() - Uploaded_) * sizeof(cl_int2), &Nodes_[Uploaded_]);
  Uploaded_ = Nodes_.size();
}

OpenCLZhengEngine::OpenCLZhengEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell,
                                     const ForceModel& model, const OpenCLOptions& options)
    : Bone_(bone), Tool_(tool), Shell_(shell), Model_(model), Rt_(options) {
  Rt_.BuildEngine([&] {
    Program_ =
        BuildOpenCLProgram(Rt_.context, Rt_.device, kernels::bmZhengFrame, Rt_.BuildOptions());
    Collide_ = cl::Kernel(Program_, "zheng_collide");
    Reduce_ = cl::Kernel(Program_, "zheng_reduce");
    Remove_ = cl::Kernel(Program_, "zheng_remove");
    const auto& dims = bone.Dims();
    const int nmax = std::max({dims[0], dims[1], dims[2]});
    while ((1 << Levels_) < nmax)
      ++Levels_;
    Nodes_.reserve(1024);
    Nodes_.push_back({{-1, 0}});
    const int32_t root = Build(Levels_, 0, 0, 0);
    Nodes_[0] = Nodes_[size_t(root)];
    UploadTree();
    const size_t n = shell.Size();
    Codes_ = Rt_.Upload(shell.Codes().data(), n * 8);
    Normals_ = Rt_.Upload(shell.AreaNormals().data(), n * 12);
    Bins_ = Rt_.Upload(shell.Bins().data(), n * 2);
    Deltas_ = Rt_.Upload(shell.Deltas().data(), n * 4);
    Radial_ = Rt_.Upload(shell.RadialDirs().data(), n * 16);
    Terms_ = Rt_.Upload(nullptr, shell.ForceBins().size() * kTerms * 8);
    Material_ =
        Rt_.Upload(bone.MaterialData(), bone.HasMaterial() ? size_t(bone.StorageSize()) * 4 : 0);
    const std::vector<ElementResidency> state(n);
    State_ = Rt_.Upload(state.data(), n * sizeof(ElementResidency), CL_MEM_READ_WRITE);
    Units_ = Rt_.Upload(nullptr, n * 4, CL_MEM_READ_WRITE);
    Buffer_ = Rt_.Upload(nullptr, n * sizeof(cl_double4), CL_MEM_READ_WRITE);
    ChunkHost_.resize((n + kChunk - 1) / kChunk);
    ChunkSums_ = Rt_.Upload(nullptr, ChunkHost_.size() * sizeof(cl_double4), CL_MEM_READ_WRITE);
    SumsHost_.assign(size_t(Rt_.groups) * kSums, 0);
    RemovalSumsHost_.assign(size_t(Rt_.groups * Rt_.lanes) * kRemovalSums, 0);
    Sums_ = Rt_.Upload(nullptr, SumsHost_.size() * 8, CL_MEM_READ_WRITE);
    RemovalSums_ = Rt_.Upload(nullptr, RemovalSumsHost_.size() * 8, CL_MEM_READ_WRITE);
    RefineCount_ = Rt_.Upload(nullptr, 4, CL_MEM_READ_WRITE);
    Refine_ = Rt_.Upload(nullptr, n * sizeof(cl_int4), CL_MEM_READ_WRITE);
    // Warm-up: one frame with every kernel launched, then the residency state reset.
    Launch(OpenCLRuntime::WarmUpFrame(), 1);
    const std::vector<ElementResidency> fresh(n);
    Rt_.queue.enqueueWriteBuffer(State_, CL_TRUE, 0, n * sizeof(ElementResidency), fresh.data());
    TermsFeed_ = TermsSpeed_ = -1;
  });
}

void OpenCLZhengEngine::UpdateTerms(double f, double n) {
  if (f == TermsFeed_ && n == TermsSpeed_)
    return;
  // The parts of ForceModel::Evaluate that do not depend on the voxel's material, per bin; the
  // kernel finishes Evaluate's arithmetic in the same order.
  const auto& bins = Shell_.ForceBins();
  TermsHost_.assign(bins.size() * kTerms, 0.0);
  for (size_t b = 0; b < bins.size(); ++b) {
    const ElementTerms t = Model_.Terms(Tool_, bins[b].kind, bins[b].r, f, n);
    const Coefficients& C =
        bins[b].kind == EdgeKind::Chisel ? Model_.ChiselCoefficients() : Model_.LipCoefficients();
    double kc = 0, kt = 0;
    for (size_t i = 0; i < t.g.size(); ++i) {
      kc += C.kc[i] * t.g[i];
      kt += C.kt[i] * t.g[i];
    }
    double* o = &TermsHost_[b * kTerms];
    o[0] = kc;
    o[1] = kt;
    o[2] = t.auPerDelta;
    for (int a = 0; a < 3; ++a) {
      o[3 + a] = t.dirN[size_t(a)];
      o[6 + a] = t.dirT[size_t(a)];
    }
    o[9] = bins[b].r;
  }
  if (!TermsHost_.empty())
    Rt_.queue.enqueueWriteBuffer(Terms_, CL_TRUE, 0, TermsHost_.size() * 8, TermsHost_.data());
  TermsFeed_ = f;
  TermsSpeed_ = n;
}

FrameResult OpenCLZhengEngine::Step(const FrameInput& in) {
  const uint32_t frameNo = ++Frame_;
  // Global bounding-box pre-check, as ZhengEngine::Step.
  if (!FrameGeometry(in, Shell_, Bone_).ToolMeetsBone(Tool_, Bone_))
    return FrameResult{};
  try {
    return Launch(in, frameNo);
  } catch (const cl::Error& e) {
    throw std::runtime_error("OpenCL frame: " + DescribeOpenCLError(e));
  }
}

FrameResult OpenCLZhengEngine::Launch(const FrameInput& in, uint32_t frameNo) {
  const bool cutting = in.speedRpm > 0 && in.feedMmPerRev > 0;
  if (cutting)
    UpdateTerms(in.feedMmPerRev, in.speedRpm);
  const FrameGeometry geo(in, Shell_, Bone_);
  const bool remove = geo.remove;
  const Eigen::Vector3d& d = geo.motionTool;
  const auto& dims = geo.dims;
  const cl_uint n = cl_uint(Shell_.Size());
  const cl_uint L = cl_uint(Rt_.lanes);
  const size_t most = size_t(Rt_.groups) * L;
  const cl_uint per = cl_uint(std::max<size_t>(1, (n + most - 1) / most));
  const cl_uint items = cl_uint(std::max<size_t>(1, (n + per - 1) / per));
  const cl_uint global = (items + L - 1) / L * L;
  const cl_uint G = global / L;
  const cl_uint nChunks = cl_uint(ChunkHost_.size());
  const cl_int flags = (remove ? 1 : 0) | (cutting ? 2 : 0) | (Bone_.HasMaterial() ? 4 : 0) |
                       (in.envelopeRemoves ? 8 : 0);
  auto f4 = [&](int row) {
    const size_t w = size_t(row);
    return cl_float4{{geo.A[3 * w], geo.A[3 * w + 1], geo.A[3 * w + 2], geo.b[w]}};
  };
  const cl_int4 dims4{{dims[0], dims[1], dims[2], 0}};
  const cl_int2 pitch{{geo.pitch[0], geo.pitch[1]}};
  auto& q = Rt_.queue;
  if (Rt_.int64Atomics) {
    q.enqueueFillBuffer(Sums_, cl_long(0), 0, kSums * 8);
    q.enqueueFillBuffer(RemovalSums_, cl_long(0), 0, kRemovalSums * 8);
  }
  q.enqueueFillBuffer(RefineCount_, cl_uint(0), 0, 4);
  int a = 0;
  cl::Kernel& k = Collide_;
  k.setArg(a++, n);
  k.setArg(a++, per);
  k.setArg(a++, Codes_);
  k.setArg(a++, Normals_);
  k.setArg(a++, Bins_);
  k.setArg(a++, Deltas_);
  k.setArg(a++, Radial_);
  k.setArg(a++, Terms_);
  k.setArg(a++, NodesDev_);
  k.setArg(a++, cl_int(Levels_));
  k.setArg(a++, Material_);
  k.setArg(a++, State_);
  k.setArg(a++, Units_);
  k.setArg(a++, Buffer_);
  k.setArg(a++, Sums_);
  k.setArg(a++, cl::Local(size_t(L) * kSums * 8));
  k.setArg(a++, RefineCount_);
  k.setArg(a++, Refine_);
  k.setArg(a++, f4(0));
  k.setArg(a++, f4(1));
  k.setArg(a++, f4(2));
  k.setArg(a++, dims4);
  k.setArg(a++, pitch);
  k.setArg(a++, cl_uint(frameNo));
  k.setArg(a++, flags);
  for (int c = 0; c < 3; ++c)
    k.setArg(a++, d(c));
  k.setArg(a++, geo.unitsPerMm3);
  k.setArg(a++, geo.maxUnits);
  q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(L));
  Reduce_.setArg(0, n);
  Reduce_.setArg(1, Buffer_);
  Reduce_.setArg(2, ChunkSums_);
  q.enqueueNDRangeKernel(Reduce_, cl::NullRange, cl::NDRange(std::max<cl_uint>(1, nChunks)),
                         cl::NullRange);
  const size_t nSums = Rt_.int64Atomics ? kSums : size_t(G) * kSums;
  cl_uint nRefine = 0;
  q.enqueueReadBuffer(Sums_, CL_FALSE, 0, nSums * 8, SumsHost_.data());
  q.enqueueReadBuffer(ChunkSums_, CL_FALSE, 0, nChunks * sizeof(cl_double4), ChunkHost_.data());
  q.enqueueReadBuffer(RefineCount_, CL_FALSE, 0, 4, &nRefine);
  q.finish();

  FrameResult res;
  if (remove) {
    if (nRefine > 0) {
      RefineHost_.resize(nRefine);
      q.enqueueReadBuffer(Refine_, CL_TRUE, 0, nRefine * sizeof(cl_int4), RefineHost_.data());
      for (const auto& r : RefineHost_)
        Refine(r.s[0], r.s[1], r.s[2]);
      UploadTree();
    }
    a = 0;
    Remove_.setArg(a++, n);
    Remove_.setArg(a++, per);
    Remove_.setArg(a++, State_);
    Remove_.setArg(a++, Units_);
    Remove_.setArg(a++, NodesDev_);
    Remove_.setArg(a++, cl_int(Levels_));
    Remove_.setArg(a++, pitch);
    Remove_.setArg(a++, RemovalSums_);
    q.enqueueNDRangeKernel(Remove_, cl::NullRange, cl::NDRange(global), cl::NDRange(L));
    const size_t nRemoval = Rt_.int64Atomics ? kRemovalSums : size_t(global) * kRemovalSums;
    q.enqueueReadBuffer(RemovalSums_, CL_TRUE, 0, nRemoval * 8, RemovalSumsHost_.data());
    for (size_t i = 0; i < nRemoval; ++i)
      (i % 2 ? res.removedVoxels : res.removedFill) += RemovalSumsHost_[i];
  }
  int64_t s[kSums] = {0, 0, 0, 0};
  for (size_t i = 0; i < nSums; ++i)
    s[i % kSums] += SumsHost_[i];
  double total[4] = {0, 0, 0, 0};
  for (const auto& c : ChunkHost_)
    for (int qn = 0; qn < 4; ++qn)
      total[qn] += c.s[qn];
  res.forceTool = {total[0], total[1], total[2]};
  res.thrustN = total[2];
  res.torqueNmm = total[3];
  res.thrustFixed = int64_t(total[2] * kForceFixedScale);
  res.torqueFixed = int64_t(total[3] * kForceFixedScale);
  res.visitedElements = s[0];
  res.engagedElements = s[1];
  res.engagedCutting = s[2];
  FrameGeometry::UnturnLateral(res, in, Shell_);
  res.removedVolumeMm3 = double(res.removedFill) / Voxmap::kFull * Bone_.VoxelVolume();
  res.sweptVolumeMm3 = double(s[3]) / Voxmap::kFull * Bone_.VoxelVolume();
  return res;
}

void OpenCLZhengEngine::SyncBone() {
  try {
    std::vector<cl_int2> nodes(Uploaded_);
    Rt_.queue.enqueueReadBuffer(NodesDev_, CL_TRUE, 0, Uploaded_ * sizeof(cl_int2), nodes.data());
    const auto& dims = Bone_.Dims();
    Voxmap::Fill* f = Bone_.MutableFill();
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          int32_t node = 0;
          int level = Levels_;
          while (nodes[size_t(node)].s[0] >= 0) {
            --level;
            const int c =
                ((i >> level) & 1) | (((j >> level) & 1) << 1) | (((k >> level) & 1) << 2);
            node = nodes[size_t(node)].s[0] + c;
          }
          f[Bone_.Index(i, j, k)] = nodes[size_t(node)].s[1];
        }
  } catch (const cl::Error& e) {
    throw std::runtime_error("OpenCL read-back: " + DescribeOpenCLError(e));
  }
  Bone_.RebuildOccupancy();
}

} // namespace bm
