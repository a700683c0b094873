#include "bmOpenCLEngine.h"

#include <algorithm>
#include <cfloat>
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
// The meta buffer (Kernels/bmVpsFrame.cl): two halves of kMeta longs.
constexpr int kMeta = 16, kMetaLog = 8, kMetaRemoval = 9;
// Argument indices of the kernels' per-frame arguments (Kernels/bmVpsFrame.cl).
constexpr int kCollideHalf = 17, kCollideA = 19, kCollideGeom = 25, kCollideFrame = 29,
              kCollideMaxUnits = 35, kRemoveFrame = 3, kRemoveHalf = 12;
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
    std::vector<float> box(blocks.size() * 12);
    std::vector<cl_uint4> info(blocks.size());
    ShellLo_ = {FLT_MAX, FLT_MAX, FLT_MAX};
    ShellHi_ = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (size_t b = 0; b < blocks.size(); ++b) {
      const ShellBlock& blk = blocks[b];
      for (int a = 0; a < 3; ++a) {
        box[12 * b + size_t(a)] = blk.lo[size_t(a)];
        box[12 * b + 3 + size_t(a)] = blk.hi[size_t(a)];
        box[12 * b + 6 + size_t(a)] = blk.nLo[size_t(a)];
        box[12 * b + 9 + size_t(a)] = blk.nHi[size_t(a)];
        ShellLo_[size_t(a)] = std::min(ShellLo_[size_t(a)], blk.lo[size_t(a)]);
        ShellHi_[size_t(a)] = std::max(ShellHi_[size_t(a)], blk.hi[size_t(a)]);
      }
      info[b] = {{blk.begin, blk.end, blk.hasCutting ? 1u : 0u, 0u}};
    }
    // Grown by one shell spacing: the culling's rounding can then never reach past it.
    for (int a = 0; a < 3; ++a) {
      ShellLo_[size_t(a)] -= float(shell.Spacing());
      ShellHi_[size_t(a)] += float(shell.Spacing());
    }
    Codes_ = Rt_.Upload(shell.Codes().data(), n * 8);
    Normals_ = Rt_.Upload(shell.AreaNormals().data(), n * 12);
    Bins_ = Rt_.Upload(shell.Bins().data(), n * 2);
    Deltas_ = Rt_.Upload(shell.Deltas().data(), n * 4);
    BlockBox_ = Rt_.Upload(box.data(), box.size() * sizeof(float));
    BlockInfo_ = Rt_.Upload(info.data(), info.size() * sizeof(cl_uint4));
    static_assert(sizeof(shell.RadialDirs()[0]) == 16, "double2 per element");
    Radial_ = Rt_.Upload(shell.RadialDirs().data(), n * 16);
    Table_ = Rt_.Upload(nullptr, shell.ForceBins().size() * sizeof(BinForce));
    Fill_ = Rt_.Upload(bone.FillData(), size_t(bone.StorageSize()) * 4, CL_MEM_READ_WRITE);
    Material_ =
        Rt_.Upload(bone.MaterialData(), bone.HasMaterial() ? size_t(bone.StorageSize()) * 4 : 0);
    const auto& bd = bone.BrickDims();
    std::vector<int32_t> bricks(size_t(bd[0]) * bd[1] * bd[2]);
    for (size_t b = 0; b < bricks.size(); ++b)
      bricks[b] = bone.BrickCount(int64_t(b));
    Bricks_ = Rt_.Upload(bricks.data(), bricks.size() * 4, CL_MEM_READ_WRITE);
    const std::vector<uint32_t> never(blocks.size(), 0);
    VisibleFrame_ = Rt_.Upload(never.data(), never.size() * 4, CL_MEM_READ_WRITE);
    const std::vector<ElementResidency> state(n);
    State_ = Rt_.Upload(state.data(), n * sizeof(ElementResidency), CL_MEM_READ_WRITE);
    Units_ = Rt_.Upload(nullptr, n * 4, CL_MEM_READ_WRITE);
    if (!Rt_.int64Atomics) {
      PartialsHost_.assign(size_t(Rt_.groups) * kSums, 0);
      RemovalPartialsHost_.assign(size_t(Rt_.groups) * kRemovalSums, 0);
    }
    Partials_ = Rt_.Upload(nullptr, PartialsHost_.size() * 8, CL_MEM_READ_WRITE);
    RemovalPartials_ = Rt_.Upload(nullptr, RemovalPartialsHost_.size() * 8, CL_MEM_READ_WRITE);
    const std::vector<int64_t> zeros(2 * kMeta, 0);
    Meta_ = Rt_.Upload(zeros.data(), zeros.size() * 8, CL_MEM_READ_WRITE);
    // The removal log: at most one merged request per element and frame.
    Log_ = Rt_.deviceHeldBone ? Rt_.Upload(nullptr, 8, CL_MEM_READ_WRITE)
                              : Rt_.Upload(nullptr, n * 16, CL_MEM_READ_WRITE);
    // The frame's sums are read into pinned host memory (a mapped buffer allocated by the
    // runtime): a read into pageable memory goes through a staging copy on some drivers.
    MetaPinned_ = cl::Buffer(Rt_.context, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, 2 * kMeta * 8);
    MetaPinnedHost_ = static_cast<int64_t*>(Rt_.queue.enqueueMapBuffer(
        MetaPinned_, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, 2 * kMeta * 8));
    SetFixedArgs();
    // Warm-up: both kernels launched once, far from any bone (nothing visible).
    Warming_ = true;
    Step(OpenCLRuntime::WarmUpFrame());
    Warming_ = false;
    Frame_ = 0;
    TableFeed_ = TableSpeed_ = -1;
  });
}

OpenCLEngine::~OpenCLEngine() {
  if (MetaPinnedHost_) {
    try {
      Rt_.queue.enqueueUnmapMemObject(MetaPinned_, MetaPinnedHost_);
      Rt_.queue.finish();
    } catch (const cl::Error&) {
      // A device lost at shutdown: nothing left to release in order.
    }
  }
}

void OpenCLEngine::SetFixedArgs() {
  const cl_uint nBlocks = cl_uint(Shell_.Blocks().size());
  const auto& dims = Bone_.Dims();
  const auto& bd = Bone_.BrickDims();
  const cl_int4 dims4{{dims[0], dims[1], dims[2], 0}};
  const cl_int2 pitch{{Bone_.Pitch()[0], Bone_.Pitch()[1]}};
  const cl_int4 bricks4{{bd[0], bd[1], bd[2], 0}};
  const size_t L = size_t(Rt_.lanes);
  int a = 0;
  cl::Kernel& k = Collide_;
  k.setArg(a++, nBlocks);
  k.setArg(a++, BlockBox_);
  k.setArg(a++, BlockInfo_);
  k.setArg(a++, Bricks_);
  k.setArg(a++, VisibleFrame_);
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
  k.setArg(a++, Partials_);
  k.setArg(a++, Meta_);
  a = kCollideHalf + 1;
  k.setArg(a++, cl::Local(L * kSums * 8));
  a = kCollideA + 3;
  k.setArg(a++, dims4);
  k.setArg(a++, pitch);
  k.setArg(a++, bricks4);
  a = kCollideFrame + 5;
  k.setArg(a++, Voxmap::kFull / Bone_.VoxelVolume()); // FrameGeometry::unitsPerMm3
  a = kCollideMaxUnits + 1;
  k.setArg(a++, kForceFixedScale);
  a = 0;
  cl::Kernel& m = Remove_;
  m.setArg(a++, nBlocks);
  m.setArg(a++, BlockInfo_);
  m.setArg(a++, VisibleFrame_);
  a = kRemoveFrame + 1;
  m.setArg(a++, State_);
  m.setArg(a++, Units_);
  m.setArg(a++, Fill_);
  m.setArg(a++, Bricks_);
  m.setArg(a++, pitch);
  m.setArg(a++, bricks4);
  m.setArg(a++, RemovalPartials_);
  m.setArg(a++, Meta_);
  a = kRemoveHalf + 1;
  m.setArg(a++, Log_);
  m.setArg(a++, cl::Local(L * kRemovalSums * 8));
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

bool OpenCLEngine::MayMeetBone(const FrameGeometry& geo) const {
  std::array<int, 3> lo, hi;
  geo.VoxelBox(ShellLo_, ShellHi_, lo, hi);
  if (!Rt_.deviceHeldBone)
    return Bone_.AnyBoneIn(lo, hi); // the host's occupancy is current
  for (int a = 0; a < 3; ++a)
    if (std::max(lo[size_t(a)], 0) > std::min(hi[size_t(a)], geo.dims[size_t(a)] - 1))
      return false;
  return true;
}

Voxmap::RemovalTotals OpenCLEngine::ApplyLog(size_t logLength) {
  LogHost_.resize(2 * logLength);
  Rt_.queue.enqueueReadBuffer(Log_, CL_TRUE, 0, logLength * 16, LogHost_.data());
  Requests_.resize(logLength);
  for (size_t i = 0; i < logLength; ++i) {
    const int64_t idx = LogHost_[2 * i];
    if (idx < 0 || idx >= Bone_.StorageSize() || LogHost_[2 * i + 1] <= 0 ||
        LogHost_[2 * i + 1] > INT32_MAX)
      throw std::runtime_error("OpenCL frame: the device's removal log is corrupt");
    Requests_[i] = {idx, int32_t(LogHost_[2 * i + 1]), int32_t(Bone_.BrickOfVoxel(idx))};
  }
  // In the order the work items flushed (any order gives the same fills and totals).
  Touched_.clear();
  const Voxmap::RemovalTotals t = Bone_.RemoveOwned(Requests_.data(), Requests_.size(), Touched_);
  Bone_.MarkBricksChanged(Touched_);
  return t;
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

  const FrameGeometry geo(in, Shell_, Bone_);
  FrameResult r;
  if (!Warming_ && !MayMeetBone(geo)) {
    // As the CPU engine: every block culled, nothing visited.
    FrameGeometry::UnturnLateral(r, in, Shell_);
    return r;
  }
  const bool remove = geo.remove;
  const Eigen::Vector3d& d = geo.motionTool;
  const cl_uint nBlocks = cl_uint(Shell_.Blocks().size());
  const cl_uint half = Half_;
  Half_ = 1 - Half_;
  try {
    auto& q = Rt_.queue;
    const cl_uint L = cl_uint(Rt_.lanes);
    const cl_uint G = std::max<cl_uint>(1, std::min<cl_uint>(cl_uint(Rt_.groups), nBlocks));
    const cl_int flags = (remove ? 1 : 0) | (cutting ? 2 : 0) | (Bone_.HasMaterial() ? 4 : 0) |
                         (in.envelopeRemoves ? 8 : 0);
    auto f4 = [&](int row) {
      const size_t w = size_t(row);
      return cl_float4{{geo.A[3 * w], geo.A[3 * w + 1], geo.A[3 * w + 2], geo.b[w]}};
    };
    // The culling's geometry in four double4 (Kernels/bmVpsFrame.cl vps_collide).
    double g[16];
    for (int row = 0; row < 3; ++row)
      for (int c = 0; c < 3; ++c)
        g[3 * row + c] = geo.rotation(row, c);
    for (int a = 0; a < 3; ++a) {
      g[9 + a] = geo.position(a);
      g[12 + a] = Bone_.Origin()[size_t(a)];
    }
    g[15] = Bone_.Spacing();
    auto d4 = [&](int q) {
      return cl_double4{{g[4 * q], g[4 * q + 1], g[4 * q + 2], g[4 * q + 3]}};
    };
    // The arguments that change from frame to frame (SetFixedArgs set the others once).
    cl::Kernel& k = Collide_;
    k.setArg(kCollideHalf, half);
    for (int row = 0; row < 3; ++row)
      k.setArg(kCollideA + row, f4(row));
    for (int q4 = 0; q4 < 4; ++q4)
      k.setArg(kCollideGeom + q4, d4(q4));
    k.setArg(kCollideFrame, cl_uint(frameNo));
    k.setArg(kCollideFrame + 1, flags);
    for (int c = 0; c < 3; ++c)
      k.setArg(kCollideFrame + 2 + c, d(c));
    k.setArg(kCollideMaxUnits, geo.maxUnits);
    q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(size_t(G) * L), cl::NDRange(L));
    if (remove) {
      Remove_.setArg(kRemoveFrame, cl_uint(frameNo));
      Remove_.setArg(kRemoveHalf, half);
      q.enqueueNDRangeKernel(Remove_, cl::NullRange, cl::NDRange(size_t(G) * L), cl::NDRange(L));
    }
    int64_t* meta = MetaPinnedHost_ + size_t(half) * kMeta;
    q.enqueueReadBuffer(Meta_, CL_FALSE, size_t(half) * kMeta * 8, kMeta * 8, meta);
    if (!Rt_.int64Atomics) {
      q.enqueueReadBuffer(Partials_, CL_FALSE, 0, size_t(G) * kSums * 8, PartialsHost_.data());
      if (remove)
        q.enqueueReadBuffer(RemovalPartials_, CL_FALSE, 0, size_t(G) * kRemovalSums * 8,
                            RemovalPartialsHost_.data());
    }
    q.finish();
    int64_t s[kSums] = {0, 0, 0, 0, 0, 0, 0, 0};
    int64_t removal[kRemovalSums] = {0, 0};
    if (Rt_.int64Atomics) {
      std::copy(meta, meta + kSums, s);
      if (remove)
        std::copy(meta + kMetaRemoval, meta + kMetaRemoval + kRemovalSums, removal);
    } else {
      for (size_t i = 0; i < size_t(G) * kSums; ++i)
        s[i % kSums] += PartialsHost_[i];
      if (remove)
        for (size_t i = 0; i < size_t(G) * kRemovalSums; ++i)
          removal[i % kRemovalSums] += RemovalPartialsHost_[i];
    }
    r.thrustFixed = s[0];
    r.torqueFixed = s[1];
    r.visitedElements = s[4];
    r.engagedElements = s[5];
    r.engagedCutting = s[6];
    r.removedFill = removal[0];
    r.removedVoxels = removal[1];
    const uint32_t logLength = uint32_t(meta[kMetaLog]);
    if (remove && !Rt_.deviceHeldBone && logLength > 0) {
      if (logLength > Shell_.Size())
        throw std::runtime_error("OpenCL frame: the device's removal log overflowed");
      const Voxmap::RemovalTotals t = ApplyLog(logLength);
      if (t.fill != r.removedFill || t.voxels != r.removedVoxels)
        throw std::runtime_error("OpenCL frame: the host's copy of the bone disagrees with the "
                                 "device's removal");
    }
    r.thrustN = double(r.thrustFixed) / kForceFixedScale;
    r.torqueNmm = double(r.torqueFixed) / kForceFixedScale;
    r.forceTool = {double(s[2]) / kForceFixedScale, double(s[3]) / kForceFixedScale, r.thrustN};
    r.removedVolumeMm3 = double(r.removedFill) / Voxmap::kFull * Bone_.VoxelVolume();
    r.sweptVolumeMm3 = double(s[7]) / Voxmap::kFull * Bone_.VoxelVolume();
  } catch (const cl::Error& e) {
    throw std::runtime_error("OpenCL frame: " + DescribeOpenCLError(e));
  }
  FrameGeometry::UnturnLateral(r, in, Shell_);
  return r;
}

std::vector<int32_t> OpenCLEngine::DeviceFills() const {
  std::vector<int32_t> fills(size_t(Bone_.StorageSize()));
  try {
    Rt_.queue.enqueueReadBuffer(Fill_, CL_TRUE, 0, fills.size() * 4, fills.data());
  } catch (const cl::Error& e) {
    throw std::runtime_error("OpenCL read-back: " + DescribeOpenCLError(e));
  }
  return fills;
}

void OpenCLEngine::SyncBone() {
  if (!Rt_.deviceHeldBone)
    return; // the host's Voxmap is current after every frame
  const std::vector<int32_t> fills = DeviceFills();
  std::copy(fills.begin(), fills.end(), Bone_.MutableFill());
  Bone_.RebuildOccupancy();
}

} // namespace bm
