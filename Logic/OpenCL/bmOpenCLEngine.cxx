#include "bmOpenCLEngine.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "bmCpuEngine.h"
#include "bmElementResidency.h"
#include "bmFrameGeometry.h"
#include "bmKernelSources.h"

namespace bm {

static_assert(sizeof(ElementResidency) == 16, "device residency layout: long, uint, uint");

namespace {
constexpr int kSums = 8, kRemovalSums = 2;
} // namespace

OpenCLEngine::OpenCLEngine(Voxmap& bone, const ToolModel& tool, const PointShell& shell,
                           const ForceModel& model, const OpenCLOptions& options)
    : Bone_(bone), Tool_(tool), Shell_(shell), Model_(model), Rt_(options) {
  Rt_.BuildEngine([&] {
    Program_ = BuildOpenCLProgram(Rt_.context, Rt_.device, kernels::bmVpsFrame, Rt_.BuildOptions());
    Collide_ = cl::Kernel(Program_, "vps_collide");
    Remove_ = cl::Kernel(Program_, "vps_remove");
    const size_t n = shell.Size();
    const auto& blocks = shell.Blocks();
    std::vector<cl_uint2> ranges(blocks.size());
    for (size_t b = 0; b < blocks.size(); ++b)
      ranges[b] = {{blocks[b].begin, blocks[b].end}};
    Codes_ = Rt_.Upload(shell.Codes().data(), n * 8);
    Normals_ = Rt_.Upload(shell.AreaNormals().data(), n * 12);
    Bins_ = Rt_.Upload(shell.Bins().data(), n * 2);
    Deltas_ = Rt_.Upload(shell.Deltas().data(), n * 4);
    Ranges_ = Rt_.Upload(ranges.data(), ranges.size() * sizeof(cl_uint2));
    static_assert(sizeof(shell.RadialDirs()[0]) == 16, "double2 per element");
    Radial_ = Rt_.Upload(shell.RadialDirs().data(), n * 16);
    Table_ = Rt_.Upload(nullptr, shell.ForceBins().size() * sizeof(BinForce));
    Fill_ = Rt_.Upload(bone.FillData(), size_t(bone.StorageSize()) * 4, CL_MEM_READ_WRITE);
    Material_ =
        Rt_.Upload(bone.MaterialData(), bone.HasMaterial() ? size_t(bone.StorageSize()) * 4 : 0);
    const std::vector<ElementResidency> state(n);
    State_ = Rt_.Upload(state.data(), n * sizeof(ElementResidency), CL_MEM_READ_WRITE);
    Units_ = Rt_.Upload(nullptr, n * 4, CL_MEM_READ_WRITE);
    Visible_ = Rt_.Upload(nullptr, blocks.size() * 4);
    SumsHost_.assign(size_t(Rt_.groups) * kSums, 0);
    RemovalSumsHost_.assign(size_t(Rt_.groups * Rt_.lanes) * kRemovalSums, 0);
    Sums_ = Rt_.Upload(nullptr, SumsHost_.size() * 8, CL_MEM_READ_WRITE);
    RemovalSums_ = Rt_.Upload(nullptr, RemovalSumsHost_.size() * 8, CL_MEM_READ_WRITE);
    VoidedCount_ = Rt_.Upload(nullptr, 4, CL_MEM_READ_WRITE);
    Voided_ =
        Rt_.Upload(nullptr, std::min<size_t>(n, size_t(bone.NumVoxels())) * 8, CL_MEM_READ_WRITE);
    Bricks_.resize(size_t(bone.BrickDims()[0]) * bone.BrickDims()[1] * bone.BrickDims()[2]);
    for (size_t b = 0; b < Bricks_.size(); ++b)
      Bricks_[b] = bone.BrickCount(int64_t(b));
    Visible_Host_.reserve(blocks.size());
    // Warm-up on an empty block list (Warming_ launches the kernels with no block visible).
    Warming_ = true;
    Step(OpenCLRuntime::WarmUpFrame());
    Warming_ = false;
    Frame_ = 0;
    TableFeed_ = TableSpeed_ = -1;
  });
}

void OpenCLEngine::UpdateForceTable(double f, double n) {
  if (f == TableFeed_ && n == TableSpeed_)
    return;
  TableHost_ = ForceTable(Tool_, Model_, ShellBinSpans(Shell_), f, n);
  static_assert(sizeof(BinForce) == 4 * sizeof(double), "double4 per bin");
  if (!TableHost_.empty())
    Rt_.queue.enqueueWriteBuffer(Table_, CL_TRUE, 0, TableHost_.size() * sizeof(BinForce),
                                 TableHost_.data());
  TableFeed_ = f;
  TableSpeed_ = n;
}

bool OpenCLEngine::AnyBoneIn(std::array<int, 3> lo, std::array<int, 3> hi) const {
  // As Voxmap::AnyBoneIn, on the engine's copy of the brick occupancy.
  const auto& dims = Bone_.Dims();
  const auto& bd = Bone_.BrickDims();
  std::array<int, 3> blo, bhi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(lo[a], 0);
    hi[a] = std::min(hi[a], dims[a] - 1);
    if (lo[a] > hi[a])
      return false;
    blo[a] = lo[a] / Voxmap::kBrick;
    bhi[a] = hi[a] / Voxmap::kBrick;
  }
  for (int bk = blo[2]; bk <= bhi[2]; ++bk)
    for (int bj = blo[1]; bj <= bhi[1]; ++bj)
      for (int bi = blo[0]; bi <= bhi[0]; ++bi)
        if (Bricks_[size_t(bi + int64_t(bd[0]) * (bj + int64_t(bd[1]) * bk))] > 0)
          return true;
  return false;
}

FrameResult OpenCLEngine::Step(const FrameInput& in) {
  const uint32_t frameNo = ++Frame_;
  const bool cutting = in.speedRpm > 0 && in.feedMmPerRev > 0;
  try {
    if (cutting)
      UpdateForceTable(in.feedMmPerRev, in.speedRpm);
  } catch (const cl::Error& e) {
    throw std::runtime_error("OpenCL frame: " + DescribeOpenCLError(e));
  }

  // Transform and culling exactly as CpuEngine::Step (bmCpuEngine.cxx), from the same
  // FrameGeometry.
  const FrameGeometry geo(in, Shell_, Bone_);
  const bool remove = geo.remove;
  const Eigen::Vector3d& d = geo.motionTool;
  const auto& dims = geo.dims;
  const auto& blocks = Shell_.Blocks();
  Visible_Host_.clear();
  for (uint32_t bi = 0; bi < blocks.size(); ++bi) {
    const ShellBlock& blk = blocks[bi];
    if (!blk.hasCutting) {
      double up = 0;
      for (int a = 0; a < 3; ++a)
        up += std::max(blk.nLo[a] * d(a), blk.nHi[a] * d(a));
      if (up <= 0 || !remove)
        continue;
    }
    std::array<int, 3> lo, hi;
    geo.VoxelBox(blk.lo, blk.hi, lo, hi);
    if (AnyBoneIn(lo, hi))
      Visible_Host_.push_back(bi);
  }

  FrameResult r;
  const cl_uint nVisible = cl_uint(Visible_Host_.size());
  if (nVisible > 0 || Warming_) {
    try {
      auto& q = Rt_.queue;
      const cl_uint G = std::max<cl_uint>(1, std::min<cl_uint>(cl_uint(Rt_.groups), nVisible));
      const cl_uint L = cl_uint(Rt_.lanes);
      const cl_uint T =
          std::max<cl_uint>(1, std::min<cl_uint>(cl_uint(Rt_.groups * Rt_.lanes), nVisible));
      q.enqueueWriteBuffer(Visible_, CL_FALSE, 0, nVisible * 4, Visible_Host_.data());
      if (Rt_.int64Atomics) {
        q.enqueueFillBuffer(Sums_, cl_long(0), 0, kSums * 8);
        q.enqueueFillBuffer(RemovalSums_, cl_long(0), 0, kRemovalSums * 8);
      }
      q.enqueueFillBuffer(VoidedCount_, cl_uint(0), 0, 4);
      const cl_int flags = (remove ? 1 : 0) | (cutting ? 2 : 0) | (Bone_.HasMaterial() ? 4 : 0) |
                           (in.envelopeRemoves ? 8 : 0);
      auto f4 = [&](int row) {
        const size_t w = size_t(row);
        return cl_float4{{geo.A[3 * w], geo.A[3 * w + 1], geo.A[3 * w + 2], geo.b[w]}};
      };
      int a = 0;
      cl::Kernel& k = Collide_;
      k.setArg(a++, Visible_);
      k.setArg(a++, nVisible);
      k.setArg(a++, Ranges_);
      k.setArg(a++, Codes_);
      k.setArg(a++, Normals_);
      k.setArg(a++, Bins_);
      k.setArg(a++, Deltas_);
      k.setArg(a++, Table_);
      k.setArg(a++, Radial_);
      k.setArg(a++, Fill_);
      k.setArg(a++, Material_);
      k.setArg(a++, State_);
      k.setArg(a++, Units_);
      k.setArg(a++, Sums_);
      k.setArg(a++, cl::Local(size_t(L) * kSums * 8));
      k.setArg(a++, f4(0));
      k.setArg(a++, f4(1));
      k.setArg(a++, f4(2));
      k.setArg(a++, cl_int4{{dims[0], dims[1], dims[2], 0}});
      k.setArg(a++, cl_int2{{geo.pitch[0], geo.pitch[1]}});
      k.setArg(a++, cl_uint(frameNo));
      k.setArg(a++, flags);
      for (int c = 0; c < 3; ++c)
        k.setArg(a++, d(c));
      k.setArg(a++, geo.unitsPerMm3);
      k.setArg(a++, geo.maxUnits);
      k.setArg(a++, kForceFixedScale);
      q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(size_t(G) * L), cl::NDRange(L));
      if (remove) {
        a = 0;
        cl::Kernel& m = Remove_;
        m.setArg(a++, Visible_);
        m.setArg(a++, nVisible);
        m.setArg(a++, Ranges_);
        m.setArg(a++, State_);
        m.setArg(a++, Units_);
        m.setArg(a++, Fill_);
        m.setArg(a++, RemovalSums_);
        m.setArg(a++, VoidedCount_);
        m.setArg(a++, Voided_);
        q.enqueueNDRangeKernel(m, cl::NullRange, cl::NDRange(T), cl::NullRange);
      }
      const size_t nSums = Rt_.int64Atomics ? kSums : size_t(G) * kSums;
      const size_t nRemoval = Rt_.int64Atomics ? kRemovalSums : size_t(T) * kRemovalSums;
      cl_uint voided = 0;
      q.enqueueReadBuffer(Sums_, CL_FALSE, 0, nSums * 8, SumsHost_.data());
      if (remove) {
        q.enqueueReadBuffer(RemovalSums_, CL_FALSE, 0, nRemoval * 8, RemovalSumsHost_.data());
        q.enqueueReadBuffer(VoidedCount_, CL_FALSE, 0, 4, &voided);
      }
      q.finish();
      int64_t s[kSums] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (size_t i = 0; i < nSums; ++i)
        s[i % kSums] += SumsHost_[i];
      int64_t fx = s[2], fy = s[3], requested = s[7];
      r.thrustFixed = s[0];
      r.torqueFixed = s[1];
      r.visitedElements = s[4];
      r.engagedElements = s[5];
      r.engagedCutting = s[6];
      if (remove) {
        for (size_t i = 0; i < nRemoval; ++i)
          (i % 2 ? r.removedVoxels : r.removedFill) += RemovalSumsHost_[i];
        if (voided > 0) {
          VoidedHost_.resize(voided);
          q.enqueueReadBuffer(Voided_, CL_TRUE, 0, size_t(voided) * 8, VoidedHost_.data());
          for (int64_t idx : VoidedHost_)
            --Bricks_[size_t(Bone_.BrickOfVoxel(idx))];
        }
      }
      r.thrustN = double(r.thrustFixed) / kForceFixedScale;
      r.torqueNmm = double(r.torqueFixed) / kForceFixedScale;
      r.forceTool = {double(fx) / kForceFixedScale, double(fy) / kForceFixedScale, r.thrustN};
      r.removedVolumeMm3 = double(r.removedFill) / Voxmap::kFull * Bone_.VoxelVolume();
      r.sweptVolumeMm3 = double(requested) / Voxmap::kFull * Bone_.VoxelVolume();
    } catch (const cl::Error& e) {
      throw std::runtime_error("OpenCL frame: " + DescribeOpenCLError(e));
    }
  }
  FrameGeometry::UnturnLateral(r, in, Shell_);
  return r;
}

void OpenCLEngine::SyncBone() {
  try {
    Rt_.queue.enqueueReadBuffer(Fill_, CL_TRUE, 0, size_t(Bone_.StorageSize()) * 4,
                                Bone_.MutableFill());
  } catch (const cl::Error& e) {
    throw std::runtime_error("OpenCL read-back: " + DescribeOpenCLError(e));
  }
  Bone_.RebuildOccupancy();
}

} // namespace bm
